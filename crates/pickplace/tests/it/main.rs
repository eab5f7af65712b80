//! Integration tests of the pickplace façade.

mod fuzz_regressions;
