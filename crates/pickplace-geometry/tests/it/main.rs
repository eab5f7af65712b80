//! Integration tests of pickplace-geometry.

mod cluster;
mod db;
mod support;
mod mesh;
mod polygon;
