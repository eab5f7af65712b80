//! Integration tests of pickplace-prm on 2-D and 7-D toy spaces with analytic obstacles.

mod defaults;
mod determinism;
mod paths;
mod persistence;
mod shortcutting;
mod timing;
mod toy;
