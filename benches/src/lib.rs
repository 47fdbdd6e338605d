//! Criterion benchmarks of flexmbd live in `benches/`; run `cargo bench -p flexmbd-benches`.
