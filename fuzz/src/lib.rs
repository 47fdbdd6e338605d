//! `flexmbd-fuzz`: a mutation fuzzer of the scene files in `models/` and of the FE
//! import readers ([`readers`]).
//!
//! Each mutant is a scene of the corpus ([`corpus`]) with one to three syntax or value
//! mutations ([`mutate`]), drawn deterministically from the campaign's seed and the
//! mutant's index. It runs in both formulations ([`execute`]: load, validate, start a
//! simulation and take a few steps) inside a worker process under a memory cap
//! ([`worker`]), supervised with a wall-clock cap ([`supervise`]); a pool of such
//! workers runs the campaign ([`campaign`]), and every defect (a panic, a hang, an abort,
//! a crash, a non-finite result reported as success, a refusal naming no field) is
//! written as a reproducer ([`findings`]) that `flexmbd-fuzz --replay FILE` runs again.
//! With `--target readers` the same machinery runs the readers of
//! `flexmbd_fe::import` on mutants of their test exports ([`readers`]).
//! See `docs/fuzzing.md`.

pub mod campaign;
pub mod corpus;
pub mod execute;
pub mod findings;
pub mod lexer;
pub mod mutate;
pub mod readers;
pub mod rng;
pub mod supervise;
pub mod worker;
