//! Integration tests of pickplace-robot.

mod common;
mod fk;
mod ik;
mod malformed;
mod srdf;
