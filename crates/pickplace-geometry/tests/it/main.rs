//! Integration tests of pickplace-geometry.

mod cluster;
mod db;
mod loaders;
mod support;
mod mesh;
mod polygon;
