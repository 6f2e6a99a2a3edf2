// Hostile names: a name that a text model cannot keep (a line break, whitespace at its ends,
// empty, NULL) or that two images share is refused or left out with a message naming the
// file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/apps/hostile_cli_fixture.h"
#include "tests/support/colmap_database_writer.h"

namespace {
namespace fs = std::filesystem;
using pgba::test::Bytes;
using pgba::test::Lines;

class HostileNamesCli : public pgba::test::HostileCli {};

// Silent wrong answer: two images of one NAME in a tracks model (evaluate --gt aligned on the
// wrong ones).
TEST_F(HostileNamesCli, DuplicateImageNameInTracksModel) {
  const fs::path model = ModelCopy("dup_name_model");
  // images.txt: comment lines, then IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME / POINTS2D.
  std::vector<std::string> lines;
  {
    std::ifstream in(model / "images.txt");
    for (std::string line; std::getline(in, line);) lines.push_back(line);
  }
  std::vector<size_t> headers;
  for (size_t i = 0; i < lines.size(); ++i)
    if (!lines[i].empty() && lines[i][0] != '#' && (headers.empty() || i > headers.back() + 1)) headers.push_back(i);
  ASSERT_GE(headers.size(), 2u);
  const std::string first_name = lines[headers[0]].substr(lines[headers[0]].rfind(' ') + 1);
  lines[headers[1]] = lines[headers[1]].substr(0, lines[headers[1]].rfind(' ') + 1) + first_name;
  {
    std::ofstream out(model / "images.txt", std::ios::trunc);
    for (const std::string& line : lines) out << line << '\n';
  }
  const std::string where = (model / "images.txt").string() + ":" + std::to_string(headers[1] + 1);
  ExpectOneLineError(Run("reconstruct --tracks " + model.string() + " --out " + (dir_ / "dup_out").string()), where,
                     "duplicate image NAME '" + first_name + "'");
  ExpectOneLineError(Run("evaluate " + (dir_ / "scene" / "gt").string() + " --obs " +
                         (dir_ / "scene" / "input").string() + " --gt " + model.string()),
                     where, "duplicate image NAME");
  EXPECT_FALSE(fs::exists(dir_ / "dup_out" / "sparse"));
}

// Names: a photo named with a line break or a trailing space broke the tracks model (or came
// back without the space); they are left out with a warning naming the folder. An empty or
// NULL name in a COLMAP database is refused naming the database.
TEST_F(HostileNamesCli, ImageNamesThatATextModelCannotKeep) {
  const fs::path images = Photos("odd_names");
  fs::copy_file(images / "im0.jpg", images / "new\nline.jpg");
  fs::copy_file(images / "im1.jpg", images / "trailing.jpg ");
  const pgba::test::CliResult r =
      Run("features --images " + images.string() + " --out " + (dir_ / "odd_names_ws").string());
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find(images.string() + ": image name 'new\\x0aline.jpg' holds a line break"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("'trailing.jpg ' begins or ends with whitespace"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "odd_names_ws" / "features" / "trailing.jpg .bin"));
  for (const std::string& name : {std::string(""), std::string("NULL")}) {
    const fs::path db = dir_ / ("name_" + std::to_string(name.size()) + ".db");
    {
      pgba::test::DbWriter w(db.string());
      w.Camera(1, 1, 100, 100, {90, 90, 50, 50});
      w.Image(1, "a.jpg", 1);
      if (name.empty()) {
        w.Image(2, "", 1);
      } else {
        // COLMAP's schema says NOT NULL; a database written by other tools may not.
        w.Sql("DROP TABLE images");
        w.Sql("CREATE TABLE images (image_id INTEGER PRIMARY KEY, name TEXT, camera_id INTEGER)");
        w.Image(1, "a.jpg", 1);
        w.Sql("INSERT INTO images (image_id, name, camera_id) VALUES (2, NULL, 1)");
      }
    }
    ExpectOneLineError(Run("match --database " + db.string() + " --out " + (dir_ / "name_ws").string()), db.string(),
                       name.empty() ? "image 2: empty image name" : "image 2: NULL image name");
  }
}

// Loop pairs naming images the model does not hold gave "loop pairs evaluated 0 / 1" and
// "n/a" without a cause: a warning names the loop file and says why.
TEST_F(HostileNamesCli, LoopPairsNamingUnknownImagesAreNamed) {
  const fs::path loop = dir_ / "unknown_loop.txt";
  std::ofstream(loop) << "nope.jpg 1 2 other.jpg 3 4\n";
  const std::string gt = (dir_ / "scene" / "gt").string();
  const pgba::test::CliResult r =
      Run("evaluate " + gt + " --obs " + (dir_ / "scene" / "input").string() + " --loop " + loop.string());
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: " + loop.string() + ": 1 of 1 loop pairs name an image that is not in " + gt),
            std::string::npos)
      << r.output;
}

}  // namespace
