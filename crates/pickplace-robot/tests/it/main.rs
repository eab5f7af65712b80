//! Integration tests of pickplace-robot.

mod collision;
mod common;
mod fk;
mod ik;
mod malformed;
mod meshes;
mod srdf;
