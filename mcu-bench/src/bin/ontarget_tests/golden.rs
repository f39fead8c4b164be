//! Golden values of the math checks (kernels, rotations, decompositions, rolling), per backend:
//! the f32 bits of every value their `close*` checks receive, in order. The source is
//! `golden.tsv` (one row per value: the check, then per backend its bits and its distance from
//! the closed form as measured on the target), written by `scripts/mcu-bench --record-golden`;
//! `build.rs` turns its columns into the tables `LIBM`, `MICROMATH` and `FAST`.

include!(concat!(env!("OUT_DIR"), "/golden_tables.rs"));
