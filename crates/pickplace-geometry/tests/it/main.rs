//! Integration tests of pickplace-geometry.

mod loaders;
mod mesh;
