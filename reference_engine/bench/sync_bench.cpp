// What a synchronisation between two threads costs on this machine: an OpenMP barrier,
// and a cache line handed from one core to the other and back. The coloured sweep meets
// one barrier per colour and sweep (about 2000 per step on the paper bed), and every
// body a row of the other thread moved is such a line, so these two figures bound what
// a second thread can buy (docs/performance.md, seventeenth installment).
#include <benchmark/benchmark.h>
#include <omp.h>

#include <atomic>

namespace {

constexpr int kRounds = 1000;  // synchronisations per timed iteration: a region's start is paid once

// Seconds per synchronisation (the report prints it with its unit).
benchmark::Counter per_round(const benchmark::State& state) {
  return benchmark::Counter(static_cast<double>(state.iterations()) * kRounds,
                            benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// kRounds barriers of a team of state.range(0) threads.
void BM_Barrier(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  for (auto _ : state) {
#pragma omp parallel num_threads(threads)
    for (int i = 0; i < kRounds; ++i) {
#pragma omp barrier
    }
  }
  state.counters["per_barrier"] = per_round(state);
}
BENCHMARK(BM_Barrier)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

// kRounds round trips of one cache line between two threads: each waits for the other's
// store before its own (a ping-pong), so a round trip is two transfers of the line.
void BM_LineRoundTrip(benchmark::State& state) {
  alignas(64) std::atomic<int> flag{0};
  bool two = true;
  for (auto _ : state) {
    flag.store(0);
#pragma omp parallel num_threads(2)
    {
      const int me = omp_get_thread_num();
      if (omp_get_num_threads() != 2) {
        two = false;  // one thread would wait for itself
      } else {
        for (int i = 0; i < kRounds; ++i) {
          const int mine = 2 * i + me;  // thread 0 moves on even values, thread 1 on odd
          while (flag.load(std::memory_order_acquire) != mine) {
          }
          flag.store(mine + 1, std::memory_order_release);
        }
      }
    }
    if (!two) {
      state.SkipWithError("OpenMP gave fewer than 2 threads (OMP_NUM_THREADS, OMP_THREAD_LIMIT)");
      break;
    }
  }
  state.counters["per_round_trip"] = per_round(state);
}
BENCHMARK(BM_LineRoundTrip)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace
