//! Integration tests of pickplace-grasp.

mod gripper_file;
mod invariants;
mod objects;
mod real;
mod support;
