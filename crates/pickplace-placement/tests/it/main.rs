//! Integration tests of pickplace-placement.
