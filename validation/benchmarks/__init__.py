"""Benchmark scripts (not tests): they print wall times, iteration counts and problem sizes."""
