//! Shared helpers of the criterion benchmarks (scene generators).
