#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <random>
#include <vector>
#include <fstream>
#include <sstream>
#include <thread>

#include "core/interval.h"
#include "util/atomic_file.h"
#include "util/dynamic_parallel.h"
#include "util/error.h"
#include "util/gnuplot.h"
#include "util/large_pages.h"
#include "util/module_loader.h"
#include "util/progress.h"
#include "util/least_key.h"
#include "util/sha256.h"
#include "util/union_find.h"
#include "util/thread_scratch.h"
#include "util/timer.h"

namespace cdbench {
namespace {

std::string read_all(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// One directory per test, removed afterwards (a directory per process was left behind by every run).
class ScratchDir : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           ("cdbench_util_" + std::to_string(getpid()) + "_" + info->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  std::string temp_dir() const { return dir_.string(); }

 private:
  std::filesystem::path dir_;
};
using AtomicFile = ScratchDir;
using Sha256 = ScratchDir;

TEST_F(AtomicFile, WritesAndReplaces) {
  const std::string path = temp_dir() + "/a.txt";
  write_file_atomically(path, [](std::ostream& o) { o << "first"; });
  EXPECT_EQ(read_all(path), "first");
  write_file_atomically(path, [](std::ostream& o) { o << "second"; });
  EXPECT_EQ(read_all(path), "second");
}

TEST_F(AtomicFile, FailureLeavesTargetAndNoTemporary) {
  const std::string dir = temp_dir();
  const std::string path = dir + "/b.txt";
  write_file_atomically(path, [](std::ostream& o) { o << "kept"; });
  EXPECT_THROW(write_file_atomically(path,
                                     [](std::ostream& o) {
                                       o << "partial";
                                       throw std::runtime_error("interrupted");
                                     }),
               std::runtime_error);
  EXPECT_EQ(read_all(path), "kept");
  for (const auto& e : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
}

TEST_F(AtomicFile, MissingDirectoryIsAnInputError) {
  EXPECT_THROW(write_file_atomically("/nonexistent-dir/x.txt", [](std::ostream& o) { o << "x"; }), InputError);
}

// Runs that write their outputs at the end check them first (util/atomic_file.h). /proc takes no
// new file even for root, so the refusals below hold whoever runs the tests.
TEST_F(AtomicFile, OutputDirectoryIsCreatedAndProbedLeavingNothing) {
  const std::string dir = temp_dir() + "/a/b";
  prepare_output_directory(dir);
  EXPECT_TRUE(std::filesystem::is_directory(dir));
  EXPECT_TRUE(std::filesystem::is_empty(dir));  // the probe file is gone
  prepare_output_directory(dir);                // an existing one is fine
  try {
    prepare_output_directory("/proc/self");
    ADD_FAILURE() << "/proc/self accepted as an output directory";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/proc/self"), std::string::npos) << e.what();
  }
  const std::string file = temp_dir() + "/f";
  write_file_atomically(file, [](std::ostream& o) { o << "x"; });
  EXPECT_THROW(prepare_output_directory(file + "/sub"), InputError);  // under a file
}

TEST_F(AtomicFile, OutputPathIsCheckedBeforeTheWork) {
  check_output_path(temp_dir() + "/new.csv");
  EXPECT_FALSE(std::filesystem::exists(temp_dir() + "/new.csv"));
  EXPECT_TRUE(std::filesystem::is_empty(temp_dir()));
  const auto refused = [](const std::string& path, const std::string& why) {
    try {
      check_output_path(path);
      ADD_FAILURE() << path << " accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path), std::string::npos) << what;
      EXPECT_NE(what.find(why), std::string::npos) << what;
    }
  };
  refused(temp_dir(), "is a directory");
  refused(temp_dir() + "/missing/x.csv", "no directory");
  refused("/proc/self/cdbench.csv", "cannot write there");
  EXPECT_THROW(check_output_path(""), InputError);
}

// A module that cannot be loaded: every path tried is named with its reason, and the variable
// that would name the right one (the CLI tests load the real modules, cli_float and cli_poses).
TEST_F(AtomicFile, ModuleThatCannotBeLoadedNamesEveryPathTried) {
  const std::string fake = temp_dir() + "/fake.so";
  write_file_atomically(fake, [](std::ostream& o) { o << "not a library"; });
  ModuleSearch s{"libcdbench_none.so", "CDBENCH_TEST_NO_SUCH_VARIABLE", "cdbench_none_module", 1, fake,
                 "the test needs its module"};
  try {
    load_module(s);
    ADD_FAILURE() << "a text file loaded as a module";
  } catch (const SetupError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("the test needs its module libcdbench_none.so", 0), 0u) << what;
    EXPECT_NE(what.find(fake + ": "), std::string::npos) << what;                     // the build tree's
    EXPECT_NE(what.find("/libcdbench_none.so: "), std::string::npos) << what;         // the installed ones
    EXPECT_NE(what.find("CDBENCH_TEST_NO_SUCH_VARIABLE"), std::string::npos) << what;  // how to name it
  }
}

TEST(Interval, OutwardRoundingMovesOneUlp) {
  EXPECT_GT(round_up(1.0), 1.0);
  EXPECT_LT(round_down(1.0), 1.0);
  EXPECT_EQ(round_up(round_down(1.0)), 1.0);
  const Interval i{1.0, 3.0};
  EXPECT_TRUE(i.contains(2.0));
  EXPECT_FALSE(i.contains(3.5));
  EXPECT_DOUBLE_EQ(i.width(), 2.0);
}

// Keys with many ties offered in shuffled orders: always the least (key, index), so the nearest-
// triangle queries answer the same whatever order a hint makes them visit triangles in. Without
// the tie rule (strict < alone) the first of the tied offers would win and this fails.
TEST(LeastKey, TheChoiceDoesNotDependOnTheOrderOfTheOffers) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<std::pair<double, std::uint32_t>> offers;
    const int n = 2 + trial % 9;
    for (int i = 0; i < n; ++i) offers.push_back({static_cast<double>(rng() % 3), rng() % 1000});
    if (trial % 7 == 0) offers.push_back({std::nan(""), 0});  // never taken
    const auto expected = *std::min_element(offers.begin(), offers.end(), [](const auto& a, const auto& b) {
      if (std::isnan(a.first) || std::isnan(b.first)) return !std::isnan(a.first) && std::isnan(b.first);
      return a < b;
    });
    for (int shuffle = 0; shuffle < 10; ++shuffle) {
      std::shuffle(offers.begin(), offers.end(), rng);
      LeastKey least;
      for (const auto& [k, i] : offers) least.offer(k, i);
      ASSERT_EQ(least.key, expected.first);
      ASSERT_EQ(least.index, expected.second);
    }
  }
}

// Large blocks come 2 MiB-aligned (advised as huge pages), small ones from operator new; both
// hold their contents through a vector's growth.
TEST(LargePageAllocator, LargeBlocksAreAlignedAndBothKindsHoldTheirContents) {
  std::vector<double, LargePageAllocator<double>> small(100, 1.5), large;
  for (std::size_t i = 0; i < (kLargeBlock / sizeof(double)) * 2; ++i) large.push_back(static_cast<double>(i));
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(large.data()) % kHugePage, 0u);
  for (std::size_t i = 0; i < large.size(); i += 4099) ASSERT_EQ(large[i], static_cast<double>(i));
  EXPECT_EQ(small[99], 1.5);
}

// One T per thread kept between uses; a nested use gets its own; other threads have theirs.
TEST(ThreadScratch, KeptBetweenUsesOwnWhenNestedAndPerThread) {
  std::vector<int>* first = nullptr;
  {
    ThreadScratch<std::vector<int>> a;
    a.get().assign(1000, 7);
    first = &a.get();
    {
      ThreadScratch<std::vector<int>> nested;  // the slot is taken: its own, empty
      EXPECT_NE(&nested.get(), first);
      EXPECT_TRUE(nested.get().empty());
      nested.get().push_back(1);
    }
    EXPECT_EQ(a.get().size(), 1000u);  // the nested one left the outer's alone
  }
  {
    ThreadScratch<std::vector<int>> again;  // the slot is free again: the same storage, as left
    EXPECT_EQ(&again.get(), first);
    EXPECT_EQ(again.get().size(), 1000u);
    again.get().clear();
  }
  std::vector<int>* other = nullptr;
  std::thread([&] {
    ThreadScratch<std::vector<int>> t;
    other = &t.get();
  }).join();
  EXPECT_NE(other, first);
}

TEST(DynamicMakespan, ItemsGoToTheThreadThatFreesUpFirst) {
  // A long first item holds one thread while the other takes the rest; a long last item starts
  // only when a thread frees up.
  EXPECT_EQ(dynamic_makespan({4, 1, 1, 1, 1}, 2), 4.0);
  EXPECT_EQ(dynamic_makespan({1, 1, 4}, 2), 5.0);
  EXPECT_EQ(dynamic_makespan({1, 1, 4}, 3), 4.0);
  EXPECT_EQ(dynamic_makespan({}, 4), 0.0);
  EXPECT_EQ(dynamic_makespan({2, 3}, 0), 5.0);  // at least one thread
  // Against a tick-by-tick simulation of the hand-out (integer costs).
  std::mt19937 rng(7);
  for (int round = 0; round < 200; ++round) {
    const int workers = 1 + static_cast<int>(rng() % 6);
    std::vector<double> costs(rng() % 40);
    for (double& c : costs) c = static_cast<double>(1 + rng() % 9);
    std::vector<int> left(static_cast<std::size_t>(workers), 0);
    std::size_t next = 0;
    int tick = 0;
    for (;;) {
      for (int& w : left)
        if (w == 0 && next < costs.size()) w = static_cast<int>(costs[next++]);
      if (next == costs.size() && std::all_of(left.begin(), left.end(), [](int w) { return w == 0; })) break;
      for (int& w : left) w = std::max(0, w - 1);
      ++tick;
    }
    EXPECT_EQ(dynamic_makespan(costs, workers), static_cast<double>(tick)) << "round " << round;
  }
}

TEST_F(Sha256, KnownVectors) {
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  const std::string path = temp_dir() + "/h.txt";
  write_file_atomically(path, [](std::ostream& o) { o << "abc"; });
  EXPECT_EQ(sha256_file(path), sha256_hex("abc"));
  EXPECT_THROW(sha256_file("/nonexistent/file"), InputError);
}

// Text quoted for gnuplot reads back unchanged through gnuplot itself, and the script runs in a
// directory whose name holds a quote and a space (the former `sh -c "cd '...'"` broke on it).
TEST(Gnuplot, QuotedTextAndAnyDirectoryName) {
  EXPECT_EQ(gnuplot_string("it's"), "'it''s'");
  EXPECT_EQ(gnuplot_string(""), "''");
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  const std::string dir = testing::TempDir() + "/gnuplot it's";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string text = "a 'quoted' name, \\ \"double\" $HOME `x`";
  std::ofstream(dir + "/p.gp") << "set print " << gnuplot_string("out.txt") << "\nprint " << gnuplot_string(text) << "\n";
  ASSERT_EQ(run_gnuplot(dir, "p.gp"), GnuplotRun::Ok);
  std::ifstream in(dir + "/out.txt");
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, text);
  std::ofstream(dir + "/bad.gp") << "this is not gnuplot\n";
  EXPECT_EQ(run_gnuplot(dir, "bad.gp"), GnuplotRun::Failed);
}

}  // namespace
// Unions from several threads at once give the sets and roots (each set's smallest index) that one
// thread gives, whatever the interleaving; find and unite agree with them.
// The heartbeat (a thread drawing at the line's pace without advance calls): finish() stops it
// at once, a short run prints nothing when stderr is not a terminal, and steps counted from several
// threads meanwhile are safe (the sanitizer builds run this too).
TEST(Progress, HeartbeatStopsPromptlyAndShortRunsStaySilent) {
  const std::filesystem::path log = std::filesystem::temp_directory_path() / "cdbench_progress_test.txt";
  std::fflush(stderr);
  const int saved = dup(STDERR_FILENO);
  ASSERT_GE(saved, 0);
  std::FILE* f = std::fopen(log.c_str(), "w");
  ASSERT_NE(f, nullptr);
  dup2(fileno(f), STDERR_FILENO);
  const auto start = std::chrono::steady_clock::now();
  {
    Progress p("test", 4000);
    p.start_heartbeat();
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
      threads.emplace_back([&p] {
        for (int k = 0; k < 1000; ++k) p.advance();
      });
    for (auto& t : threads) t.join();
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    p.finish();
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::fflush(stderr);
  dup2(saved, STDERR_FILENO);
  close(saved);
  std::fclose(f);
  EXPECT_LT(seconds, 2.0);
  EXPECT_EQ(std::filesystem::file_size(log), 0u);
  std::filesystem::remove(log);
}

TEST(UnionFind, ConcurrentUnionsGiveTheSerialSetsAndRoots) {
  const std::size_t n = 200000;
  std::mt19937_64 rng(7);
  std::vector<std::pair<std::size_t, std::size_t>> pairs(150000);
  for (auto& p : pairs) p = {rng() % n, rng() % n};
  UnionFind serial(n);
  for (const auto& p : pairs) serial.unite(p.first, p.second);
  for (int round = 0; round < 3; ++round) {
    UnionFind shared(n);
    std::vector<std::thread> threads;
    const std::size_t t_count = 4;
    for (std::size_t t = 0; t < t_count; ++t)
      threads.emplace_back([&, t] {
        // Each thread takes every t_count-th pair, odd threads from the last of theirs backwards.
        std::vector<std::size_t> mine;
        for (std::size_t k = t; k < pairs.size(); k += t_count) mine.push_back(k);
        if (t % 2) std::reverse(mine.begin(), mine.end());
        for (std::size_t k : mine) shared.unite_concurrent(pairs[k].first, pairs[k].second);
      });
    for (auto& th : threads) th.join();
    std::size_t sets = 0;
    for (std::size_t i = 0; i < n; ++i) {
      ASSERT_EQ(shared.find(i), serial.find(i)) << "element " << i << ", round " << round;
      sets += serial.find(i) == i;
      ASSERT_LE(serial.find(i), i);  // the root is the set's smallest index
    }
    EXPECT_GT(sets, 1000u);  // the pairs leave many sets (a test that one big set would not make)
    EXPECT_LT(sets, n / 2);
  }
}

// The thread's CPU clock runs while it computes and stands while it sleeps (bench_poses reads a
// loaded machine from the two clocks' ratio). Bounds far from any scheduler's noise.
TEST(ThreadCpuTimer, CountsWorkNotSleep) {
  const Timer wall;
  const ThreadCpuTimer cpu;
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const double slept = cpu.seconds();
  EXPECT_GE(wall.seconds(), 0.2);
  EXPECT_LT(slept, 0.05) << "the thread's CPU time grew while it slept";
  volatile double x = 0.0;
  while (cpu.seconds() < slept + 0.05) x = x + std::sqrt(x + 1.0);
  EXPECT_GE(cpu.seconds(), slept + 0.05);
  EXPECT_LE(cpu.seconds(), wall.seconds() + 1e-3) << "a thread cannot run longer than the wall clock";
}

}  // namespace cdbench
