//! Integration tests of pickplace-placement.

mod candidates;
mod rest;
mod resting;
mod simulate;
mod suite;
