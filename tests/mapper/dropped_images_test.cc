// The images a reconstruction left out, each with the first stage that left it out: no track, no
// verified pair, the global initialisation, the global BA; the console line groups them by
// reason and counts them against the input.
#include "mapper/dropped_images.h"

#include <gtest/gtest.h>

namespace pgba {
namespace {

TEST(DroppedImages, EachWithTheFirstStageThatLeftItOut) {
  Reconstruction tracks;
  tracks.cameras[1].camera_id = 1;
  // Images 1..6 named in reverse order of their ids ("f.jpg" is image 1), each with two features.
  for (uint32_t id = 1; id <= 6; ++id) {
    Image& im = tracks.images[id];
    im.image_id = id;
    im.name = std::string(1, static_cast<char>('a' + 6 - id)) + ".jpg";
    im.camera_id = 1;
    im.points2D.resize(2);
  }
  // Images 1-5 share tracks; image 6 ("a.jpg") has none.
  tracks.AddPoint3D(Eigen::Vector3d::Zero(), {{1, 0}, {2, 0}, {3, 0}});
  tracks.AddPoint3D(Eigen::Vector3d::Zero(), {{1, 1}, {4, 0}, {5, 0}});
  PointlessMapperResult r;
  // Image 5 ("b.jpg") in no verified pair; image 4 ("c.jpg") left out by the averaging; image 3
  // ("d.jpg") by the global BA; images 1 and 2 registered.
  r.initial.pairs = {{1, 2}, {1, 3}, {2, 3}, {1, 4}};
  r.initial.init.dropped_image_ids = {4, 5, 6};
  r.refined.poses[1] = Pose();
  r.refined.poses[2] = Pose();
  const std::vector<DroppedImage> dropped = DroppedImages(tracks, r);
  ASSERT_EQ(dropped.size(), 4u);
  EXPECT_EQ(dropped[0].name, "a.jpg");
  EXPECT_EQ(dropped[0].reason, "no feature matched to another image");
  EXPECT_EQ(dropped[1].name, "b.jpg");
  EXPECT_EQ(dropped[1].reason, "no image pair verified (too few matches agreeing on one relative pose)");
  EXPECT_EQ(dropped[2].name, "c.jpg");
  EXPECT_EQ(dropped[2].reason, "not connected to the others by consistent image triplets");
  EXPECT_EQ(dropped[3].name, "d.jpg");
  EXPECT_EQ(dropped[3].reason, "its triplets were unusable in the global bundle adjustment");
  EXPECT_EQ(DroppedImagesJson(dropped).size(), 4u);
  EXPECT_EQ(DroppedImagesJson(dropped)["c.jpg"], dropped[2].reason);

  // One line, the names grouped by reason.
  std::vector<DroppedImage> same = {{"x.jpg", "no feature matched to another image"},
                                    {"y.jpg", "no image pair verified"},
                                    {"z.jpg", "no feature matched to another image"}};
  const std::string line = DroppedImagesSummary(same, 10);
  EXPECT_EQ(line.rfind("3 of 10 images not registered; no feature matched to another image: x.jpg, z.jpg; no image "
                       "pair verified: y.jpg. ",
                       0),
            0u)
      << line;
  EXPECT_EQ(line.find('\n'), std::string::npos);
  EXPECT_EQ(DroppedImagesSummary({}, 10), "");
}

}  // namespace
}  // namespace pgba
