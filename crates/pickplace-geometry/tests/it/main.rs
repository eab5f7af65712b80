//! Integration tests of pickplace-geometry.

mod cluster;
mod db;
mod loaders;
mod mesh;
mod polygon;
mod support;
