// The calling thread's share [begin, end) of n items split in order among the threads of
// the enclosing parallel region (all of them outside one): for passes whose result is
// put together share by share in thread order, the same for any thread count.
#pragma once

#include <omp.h>

namespace ratchet {

struct ThreadShare {
  int begin, end;
};

inline ThreadShare thread_share(int n) {
  const long long threads = omp_get_num_threads(), me = omp_get_thread_num();
  return {static_cast<int>(n * me / threads), static_cast<int>(n * (me + 1) / threads)};
}

}  // namespace ratchet
