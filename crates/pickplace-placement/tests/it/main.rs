//! Integration tests of pickplace-placement.

mod resting;
mod simulate;
