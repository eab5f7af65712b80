//! The workspace's one seeded generator ([`Rng`], from `pickplace-base`), and the named
//! streams of this crate's planners.

pub use pickplace_base::rng::Rng;

/// Named streams, so that samples, growth and shortcuts never share random numbers.
pub(crate) mod stream {
    pub(crate) const ROADMAP_SAMPLE: u64 = 1;
    pub(crate) const GROWTH_SAMPLE: u64 = 2;
    pub(crate) const SHORTCUT: u64 = 3;
    pub(crate) const RRT: u64 = 4;
}
