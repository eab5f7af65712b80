//! Integration tests of pickplace-grasp.

mod fuzz_regressions;
mod gripper_file;
mod invariants;
mod objects;
mod real;
mod support;
