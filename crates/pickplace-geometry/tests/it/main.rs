//! Integration tests of pickplace-geometry.

mod cluster;
mod support;
mod mesh;
