"""Benchmark scripts (not tests): they print wall times, iteration counts and problem sizes."""

import time


def best_of(fn, repeat: int):
    """(shortest wall time [s] of ``repeat`` calls of ``fn``, the last call's result): the minimum
    is the run least disturbed by other load on the machine."""
    best, out = float("inf"), None
    for _ in range(max(1, repeat)):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out
