//! Integration tests of the pickplace façade.
