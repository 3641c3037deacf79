"""std::mt19937_64 in pure Python, bit for bit, and the engine's mappings to doubles.

The engine (reference_engine/src/ratchet/core/random.hpp) draws every random number of
a generated scene from one std::mt19937_64 seeded with the scene's `seed`, and maps a
draw to a double in [0, 1) with (rng() >> 11) * 2^-53. numpy has no 64-bit Mersenne
Twister, so it is written out here with the standard constants (C++ [rand.predef]:
the 10000th output of a default-constructed std::mt19937_64, seed 5489, is
9981545732273789042).
"""

_W = 64
_N = 312
_M = 156
_R = 31
_A = 0xB5026F5AA96619E9
_U, _D = 29, 0x5555555555555555
_S, _B = 17, 0x71D67FFFEDA60000
_T, _C = 37, 0xFFF7EEE000000000
_L = 43
_F = 6364136223846793005
_MASK = (1 << 64) - 1
_LOWER = (1 << _R) - 1
_UPPER = _MASK ^ _LOWER

DEFAULT_SEED = 5489


class MT19937_64:
    """The 64-bit Mersenne Twister of the C++ standard (std::mt19937_64)."""

    def __init__(self, seed=DEFAULT_SEED):
        self.seed(seed)

    def seed(self, seed):
        mt = [0] * _N
        mt[0] = seed & _MASK
        for i in range(1, _N):
            prev = mt[i - 1]
            mt[i] = (_F * (prev ^ (prev >> (_W - 2))) + i) & _MASK
        self._mt = mt
        self._index = _N

    def _twist(self):
        mt = self._mt
        for i in range(_N):
            y = (mt[i] & _UPPER) | (mt[(i + 1) % _N] & _LOWER)
            v = mt[(i + _M) % _N] ^ (y >> 1)
            if y & 1:
                v ^= _A
            mt[i] = v
        self._index = 0

    def __call__(self):
        """Next 64-bit output (an int in [0, 2^64))."""
        if self._index >= _N:
            self._twist()
        y = self._mt[self._index]
        self._index += 1
        y ^= (y >> _U) & _D
        y ^= (y << _S) & _B
        y ^= (y << _T) & _C
        y ^= y >> _L
        return y & _MASK

    def discard(self, n):
        for _ in range(n):
            self()


def uniform01(rng):
    """Engine's uniform01: a double in [0, 1) from the top 53 bits of one draw."""
    return float(rng() >> 11) * (2.0 ** -53)


def uniform(rng, lo, hi):
    """Engine's uniform(rng, lo, hi) = lo + (hi - lo) * uniform01(rng), same rounding."""
    return lo + (hi - lo) * uniform01(rng)
