//! Integration tests of pickplace-geometry.

mod cluster;
mod cluster_audit;
mod cluster_real;
mod db;
mod fuzz_regressions;
mod loaders;
mod mesh;
mod polygon;
mod support;
mod timing;
