//! Integration tests of pickplace-placement.

mod candidates;
mod resting;
mod simulate;
mod suite;
