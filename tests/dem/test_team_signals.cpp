// Point-to-point waits between threads (dem/team_signals.hpp): a thread that waits for another's
// post of an epoch sees everything that thread wrote before posting it, for epoch after epoch, with
// as many threads as cores and with more (the waits must then give up their core). That the step's
// results do not depend on these waits is the determinism tests' part (1 to 4 threads, same bits).
#include <catch2/catch.hpp>

#include <omp.h>

#include <cstdint>
#include <vector>

#include "dem/team_signals.hpp"

using namespace grainscale::dem;

TEST_CASE("A thread that waits for a post sees what was written before it", "[dem][threads][signals]") {
  const int threads = GENERATE(2, 4);
  constexpr int kRounds = 2000;
  constexpr std::size_t kWords = 64;  // several cache lines, written one by one before each post
  TeamSignals signals;
  signals.reserve(threads);
  std::vector<std::uint64_t> epochs(kRounds);
  for (std::uint64_t& e : epochs) e = signals.next_epoch();
  // Thread t writes its block, then posts; thread t + 1 waits for that post and checks the block,
  // round after round: a relay around the team, so every thread both posts and waits.
  std::vector<std::vector<std::uint64_t>> block(threads, std::vector<std::uint64_t>(kWords, 0));
  std::vector<int> mismatches(threads, 0);
#pragma omp parallel num_threads(threads)
  {
    const int team = omp_get_num_threads(), t = omp_get_thread_num();
    const int before = (t + team - 1) % team;
    for (int r = 0; r < kRounds; ++r) {
      const std::uint64_t e = epochs[r];
      if (r > 0 || t > 0) signals.wait(before, t == 0 ? epochs[r - 1] : e);  // the relay's order
      for (std::size_t w = 0; w < kWords; ++w) mismatches[t] += t > 0 && block[before][w] != e;
      for (std::size_t w = 0; w < kWords; ++w) block[t][w] = e;
      signals.post(t, e);
    }
  }
  for (int t = 0; t < threads; ++t) CHECK(mismatches[t] == 0);
}

TEST_CASE("A wait for an epoch already posted, or passed, returns at once", "[dem][threads][signals]") {
  TeamSignals signals;
  signals.reserve(2);
  const std::uint64_t first = signals.next_epoch(), second = signals.next_epoch();
  REQUIRE(second > first);
  signals.post(1, second);
  signals.wait(1, first);   // an earlier epoch: passed
  signals.wait(1, second);  // this one: posted
  // A copy (of a simulation) keeps counting from where the original was, with no posts of its own.
  TeamSignals copy = signals;
  copy.reserve(2);
  CHECK(copy.next_epoch() > second);
}

TEST_CASE("A meet: thread 0's serial part sees every thread's work, and every thread sees its result",
          "[dem][threads][signals]") {
  // The steps' region meets twice a step (Simulation::steps_in_region): each thread writes its part
  // (its largest displacement), thread 0 combines them and decides, the others read the decision.
  const int threads = GENERATE(1, 2, 4);
  constexpr int kRounds = 2000;
  TeamSignals signals;
  signals.reserve(threads);
  const std::uint64_t base = signals.next_epochs(2 * kRounds);
  CHECK(signals.next_epoch() == base + 2 * kRounds);  // the epochs taken are not given again
  std::vector<std::uint64_t> part(threads, 0);
  std::uint64_t total = 0;  // written by thread 0 in the serial part
  std::vector<int> wrong_total(threads, 0), wrong_parts(threads, 0);
#pragma omp parallel num_threads(threads)
  {
    const int team = omp_get_num_threads(), t = omp_get_thread_num();
    for (int r = 0; r < kRounds; ++r) {
      const std::uint64_t e = base + 2 * r;
      part[t] = static_cast<std::uint64_t>(r) * 100 + t;
      signals.meet(team, t, e, e + 1, [&] {
        std::uint64_t sum = 0;
        for (int u = 0; u < team; ++u) {
          wrong_parts[0] += part[u] != static_cast<std::uint64_t>(r) * 100 + u;
          sum += part[u];
        }
        total = sum;
      });
      const std::uint64_t expected = static_cast<std::uint64_t>(r) * 100 * team + team * (team - 1) / 2;
      wrong_total[t] += total != expected;
      // (Thread 0 writes `total` again only after every thread has arrived at the next meet, so
      // after each has read this one.)
    }
  }
  for (int t = 0; t < threads; ++t) {
    CHECK(wrong_total[t] == 0);
    CHECK(wrong_parts[t] == 0);
  }
}

TEST_CASE("A team larger than the processors spins briefly, whatever size was reserved before",
          "[dem][threads][signals]") {
  // reserve() counts the processors only when the team size changes (the count is a system call and
  // the force loop reserves every step), so a change of size must still choose afresh.
  const int procs = omp_get_num_procs();
  TeamSignals signals;
  signals.reserve(procs + 1);
  CHECK(signals.spins_before_yield() == TeamSignals::kSpinsOversubscribed);
  signals.reserve(procs + 1);  // the same size again: the same choice
  CHECK(signals.spins_before_yield() == TeamSignals::kSpinsOversubscribed);
  signals.reserve(1);
  CHECK(signals.spins_before_yield() == TeamSignals::kSpinsBeforeYield);
  signals.reserve(procs);  // as many threads as processors: not oversubscribed
  CHECK(signals.spins_before_yield() == TeamSignals::kSpinsBeforeYield);
  signals.reserve(procs + 2);
  CHECK(signals.spins_before_yield() == TeamSignals::kSpinsOversubscribed);
}
