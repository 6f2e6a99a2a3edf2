// report.json: stage records and an atomic write.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "pgba/io/report.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

TEST(Report, StagesAndAtomicWrite) {
  const fs::path dir = fs::temp_directory_path() / ("pgba_report_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  Report report;
  {
    StageTimer t(&report, "triplets");
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    t.Stop()["num_triplets"] = 12;
  }
  { StageTimer t(&report, "averaging"); }  // recorded on destruction
  report["images_registered"] = 70;
  report["images_dropped"] = std::vector<std::string>{"a.jpg"};

  const nlohmann::json& j = report.json();
  EXPECT_GE(j["stages"]["triplets"]["seconds"].get<double>(), 0.045);
  EXPECT_LT(j["stages"]["averaging"]["seconds"].get<double>(), 0.045);
  EXPECT_GT(j["stages"]["triplets"]["peak_rss_mb"].get<double>(), 1.0);
  EXPECT_EQ(j["stages"]["triplets"]["num_triplets"].get<int>(), 12);
  EXPECT_EQ(j["stages"]["triplets"]["order"].get<int>(), 0);
  EXPECT_EQ(j["stages"]["averaging"]["order"].get<int>(), 1);
  report.AddStage("triplets", 1.0);  // re-recorded: keeps its place
  EXPECT_EQ(report.json()["stages"]["triplets"]["order"].get<int>(), 0);

  const fs::path path = dir / "out" / "report.json";
  report.Write(path.string());
  std::ifstream in(path);
  const nlohmann::json back = nlohmann::json::parse(in);
  EXPECT_EQ(back, report.json());
  EXPECT_EQ(std::distance(fs::directory_iterator(dir / "out"), fs::directory_iterator()), 1);

  // A failed write leaves the previous report intact and no temporary behind.
  std::ofstream(dir / "blocker") << "x";
  EXPECT_ANY_THROW(report.Write((dir / "blocker" / "report.json").string()));
  EXPECT_EQ(nlohmann::json::parse(std::ifstream(path)), back);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 2);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace pgba
