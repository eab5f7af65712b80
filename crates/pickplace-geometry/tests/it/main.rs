//! Integration tests of pickplace-geometry.

mod mesh;
