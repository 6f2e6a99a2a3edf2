// report.json: stage records and an atomic write.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

#include "pgba/io/report.h"
#include "pgba/util/cpu_time.h"
#include "pgba/util/timer.h"
#include "pgba/util/timer.h"

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
  EXPECT_FALSE(report.json()["stages"]["triplets"].contains("cpu_seconds"));  // given no CPU time

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

// A stage's CPU time is the process' user + system time over it (getrusage), not its wall
// time: a sleeping stage costs none, a stage that computes for 0.2 s of this thread's CPU
// time (another clock, CLOCK_THREAD_CPUTIME_ID) costs at least that, however long the
// machine's load made it in wall time.
TEST(Report, StagesRecordTheirCpuTimeAndTheLoad) {
  Report report;
  {
    StageTimer t(&report, "sleeping");
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  {
    StageTimer t(&report, "computing");
    const double start = ThreadCpuSeconds();
    volatile double x = 0;
    while (ThreadCpuSeconds() - start < 0.2) x = x + 1.0;
  }
  const nlohmann::json& st = report.json()["stages"];
  EXPECT_GE(st["sleeping"]["seconds"].get<double>(), 0.095);
  EXPECT_LT(st["sleeping"]["cpu_seconds"].get<double>(), 0.03);
  EXPECT_GE(st["computing"]["cpu_seconds"].get<double>(), 0.19);
  EXPECT_GE(st["computing"]["seconds"].get<double>(), 0.19);  // one thread: wall >= its CPU time
  EXPECT_GE(st["computing"]["load_average"].get<double>(), 0.0);
}

// Each stage records its own peak resident memory: a stage that touches 256 MiB and frees
// them peaks that much above the next stage, which allocates nothing, and the process' peak
// keeps the first stage's. Where the kernel cannot reset the peak (clear_refs), every stage
// reports the process' peak so far, and only the ordering of the first two holds.
TEST(Report, StagesRecordTheirOwnPeakMemory) {
  Report report;
  constexpr size_t kBytes = size_t(256) << 20;
  {
    StageTimer t(&report, "allocating");
    std::vector<char> block(kBytes, 1);
    volatile char sink = block[kBytes / 2];
    (void)sink;
  }
  const bool resettable = ResetPeakRss();
  { StageTimer t(&report, "idle"); }
  const nlohmann::json& j = report.json();
  const double allocating = j["stages"]["allocating"]["peak_rss_mb"].get<double>();
  const double idle = j["stages"]["idle"]["peak_rss_mb"].get<double>();
  EXPECT_GE(allocating, 256.0);
  EXPECT_GE(j["peak_rss_mb"].get<double>(), allocating - 1.0);
  EXPECT_LE(j["stages"]["idle"]["rss_mb"].get<double>(), idle + 1.0);
  if (resettable) EXPECT_LT(idle, allocating - 200.0);
}

// A scope sees the peaks of the scopes nested in it, though each of those resets the
// kernel's peak (to 1 MiB: the kernel's resident counts lag by a few pages).
TEST(PeakRssScope, NestedScopesKeepTheOuterPeak) {
  PeakRssScope outer;
  double inner_peak = 0.0;
  {
    PeakRssScope inner;
    std::vector<char> block(size_t(128) << 20, 1);
    volatile char sink = block[block.size() / 2];
    (void)sink;
    inner_peak = inner.PeakMb();
  }
  { PeakRssScope after; }  // resets the kernel's peak once more
  EXPECT_GE(inner_peak, 128.0);
  EXPECT_GE(outer.PeakMb(), inner_peak - 1.0);
  EXPECT_GE(ProcessPeakRssMb(), inner_peak - 1.0);
}

}  // namespace
}  // namespace pgba
