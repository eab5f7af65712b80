//! Integration tests of pickplace-view.
