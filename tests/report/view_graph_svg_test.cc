// The view graph picture of report.html: one circle per input image in name order (hollow
// when not registered, filled in its model's colour otherwise), one line per verified pair,
// drawn from the tracks model, the pairs and the final models.
#include "report/view_graph_svg.h"

#include <gtest/gtest.h>

#include "report/html_report.h"

namespace pgba {
namespace {

size_t Count(const std::string& s, const std::string& what) {
  size_t n = 0;
  for (size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

TEST(ViewGraphSvg, ImagesInNameOrderPairsAsLinesDroppedImagesHollow) {
  Reconstruction tracks, model;
  // Ids out of name order: the picture follows the names.
  const char* names[] = {"c.png", "a.png", "b.png", "d.png"};
  for (uint32_t id = 1; id <= 4; ++id) {
    Image im;
    im.image_id = id;
    im.name = names[id - 1];
    tracks.images[id] = im;
    if (id != 4) model.images[id] = im;  // d.png not registered
  }
  std::vector<TwoViewGeometry> pairs(2);
  pairs[0].image_id1 = 2, pairs[0].image_id2 = 3, pairs[0].num_inliers = 120;  // a - b
  pairs[1].image_id1 = 1, pairs[1].image_id2 = 4, pairs[1].num_inliers = 15;   // c - d
  const ViewGraphPicture g = MakeViewGraphPicture(tracks, pairs, {&model});
  ASSERT_EQ(g.images.size(), 4u);
  EXPECT_EQ(g.images[0].name, "a.png");
  EXPECT_EQ(g.images[3].name, "d.png");
  EXPECT_FALSE(g.images[3].registered());
  EXPECT_EQ(g.images[0].model, 0);
  ASSERT_EQ(g.edges.size(), 2u);
  EXPECT_EQ(g.edges[0].a, 0);
  EXPECT_EQ(g.edges[0].b, 1);
  EXPECT_EQ(g.edges[1].a, 2);
  EXPECT_EQ(g.edges[1].b, 3);

  const std::string svg = ViewGraphSvg(g);
  EXPECT_EQ(Count(svg, "<circle"), 4u);
  EXPECT_EQ(Count(svg, "<line"), 2u);
  EXPECT_EQ(Count(svg, "fill=\"white\" stroke=\"#d62728\""), 1u);  // d.png
  EXPECT_NE(svg.find("c.png - d.png: 15 inliers"), std::string::npos);

  // In words: a (1) - b (2) with 120 inliers, c (3) - d (4) with 15, d not registered.
  const std::string table = ViewGraphTable(g);
  EXPECT_EQ(Count(table, "<tr>"), 5u);
  EXPECT_NE(table.find("<td>1</td><td>a.png</td><td>0</td><td>2 (120)</td>"), std::string::npos);
  EXPECT_NE(table.find("<td>2</td><td>b.png</td><td>0</td><td>1 (120)</td>"), std::string::npos);
  EXPECT_NE(table.find("<td>4</td><td>d.png</td><td><b>no</b></td><td>3 (15)</td>"), std::string::npos);

  HtmlReportInput in;
  in.title = "t";
  in.view_graph = &g;
  const std::string html = RunReportHtml(in);
  EXPECT_NE(html.find("<h2>View graph</h2>"), std::string::npos);
  EXPECT_NE(html.find(table), std::string::npos);
}

TEST(ViewGraphSvg, EachModelInItsOwnColourPairsBetweenModelsGrey) {
  Reconstruction tracks, largest, second;
  const char* names[] = {"a.png", "b.png", "c.png", "d.png", "e.png"};
  for (uint32_t id = 1; id <= 5; ++id) {
    Image im;
    im.image_id = id;
    im.name = names[id - 1];
    tracks.images[id] = im;
    if (id <= 3) largest.images[id] = im;
    if (id == 4 || id == 5) second.images[id] = im;
  }
  std::vector<TwoViewGeometry> pairs(3);
  pairs[0].image_id1 = 1, pairs[0].image_id2 = 2, pairs[0].num_inliers = 100;  // within model 0
  pairs[1].image_id1 = 4, pairs[1].image_id2 = 5, pairs[1].num_inliers = 100;  // within model 1
  pairs[2].image_id1 = 3, pairs[2].image_id2 = 4, pairs[2].num_inliers = 30;   // between them
  const ViewGraphPicture g = MakeViewGraphPicture(tracks, pairs, {&largest, &second});
  ASSERT_EQ(g.images.size(), 5u);
  EXPECT_EQ(g.images[2].model, 0);
  EXPECT_EQ(g.images[3].model, 1);
  EXPECT_EQ(g.images[4].model, 1);
  const std::string svg = ViewGraphSvg(g);
  // Model 0 blue: 3 circles (fill and stroke) and its pair; model 1 green: 2 circles and its
  // pair; the pair between the models grey.
  EXPECT_EQ(Count(svg, "fill=\"#1f77b4\" stroke=\"#1f77b4\""), 3u);
  EXPECT_EQ(Count(svg, "fill=\"#2ca02c\" stroke=\"#2ca02c\""), 2u);
  EXPECT_EQ(Count(svg, "stroke=\"#1f77b4\" stroke-opacity"), 1u);
  EXPECT_EQ(Count(svg, "stroke=\"#2ca02c\" stroke-opacity"), 1u);
  EXPECT_EQ(Count(svg, "stroke=\"#999999\" stroke-opacity"), 1u);
  EXPECT_NE(svg.find("d.png (model 1)"), std::string::npos);
  EXPECT_NE(ViewGraphTable(g).find("<td>4</td><td>d.png</td><td>1</td><td>3 (30), 5 (100)</td>"), std::string::npos);
}

}  // namespace
}  // namespace pgba
