//! Toy worlds: balls and boxes in the space's weighted metric, with exact clearance.
//!
//! Clearance (the weighted distance to the nearest obstacle) is 1-Lipschitz in the weighted
//! metric. A planner that checks states at spacing `r` against obstacles inflated by `r / 2`
//! therefore returns motions that are valid for the true obstacles at any finer resolution: the
//! property tests re-check at `r / 10`.

use pickplace_prm::JointSpace;

/// An obstacle in joint space.
#[derive(Clone, Debug)]
pub enum Obstacle {
    /// A ball of the weighted metric.
    Ball { center: Vec<f64>, radius: f64 },
    /// An axis-aligned box.
    Cuboid { lower: Vec<f64>, upper: Vec<f64> },
}

/// A space with obstacles.
#[derive(Clone, Debug)]
pub struct World {
    pub space: JointSpace,
    pub obstacles: Vec<Obstacle>,
}

impl World {
    /// Weighted distance from `q` to the nearest obstacle (0 inside one).
    pub fn clearance(&self, q: &[f64]) -> f64 {
        let w = self.space.weights();
        self.obstacles
            .iter()
            .map(|obstacle| match obstacle {
                Obstacle::Ball { center, radius } => {
                    (self.space.distance(q, center) - radius).max(0.0)
                }
                Obstacle::Cuboid { lower, upper } => q
                    .iter()
                    .zip(lower.iter().zip(upper))
                    .zip(w)
                    .map(|((x, (lo, hi)), w)| {
                        let d = (lo - x).max(x - hi).max(0.0);
                        w * d * d
                    })
                    .sum::<f64>()
                    .sqrt(),
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// The true validity: strictly outside every obstacle.
    pub fn free(&self, q: &[f64]) -> bool {
        self.clearance(q) > 0.0
    }

    /// The planning validity at `resolution`: clearance above half the resolution.
    pub fn free_at(&self, q: &[f64], resolution: f64) -> bool {
        self.clearance(q) > 0.5 * resolution
    }

    /// A state drawn from `seed` (splitmix64) that satisfies the planning validity.
    pub fn free_state(&self, seed: u64, resolution: f64) -> Vec<f64> {
        let mut state = seed;
        let mut next = move || {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        loop {
            let q: Vec<f64> = self
                .space
                .lower()
                .iter()
                .zip(self.space.upper())
                .map(|(lo, hi)| lo + next() * (hi - lo))
                .collect();
            if self.free_at(&q, resolution) {
                return q;
            }
        }
    }
}

/// The unit square with two staggered walls and a block between them: every crossing from left
/// to right winds through the gaps.
pub fn world_2d() -> World {
    let cuboid = |lower: [f64; 2], upper: [f64; 2]| Obstacle::Cuboid {
        lower: lower.to_vec(),
        upper: upper.to_vec(),
    };
    World {
        space: JointSpace::with_unit_weights(vec![0.0; 2], vec![1.0; 2]).expect("space"),
        obstacles: vec![
            cuboid([0.30, 0.0], [0.35, 0.7]),
            cuboid([0.65, 0.3], [0.70, 1.0]),
            cuboid([0.45, 0.4], [0.55, 0.6]),
        ],
    }
}

/// A 7-joint arm-like space (bounds and weights of a 6-DOF arm plus a waist) with a slab across
/// the first joint that has one opening, and eight balls.
pub fn world_7d() -> World {
    let lower = vec![-2.8, -2.9, -2.4, -2.8, -1.8, -2.9, -2.9];
    let upper = vec![2.8, 1.5, 0.3, 2.8, 1.8, 2.9, 2.9];
    let weights = vec![2.0, 1.5, 1.5, 1.0, 0.8, 0.5, 0.3];
    let space = JointSpace::new(lower.clone(), upper.clone(), weights).expect("space");
    let mut obstacles = Vec::new();
    // Slab |q0| < 0.15, open where q1 > 0.3 (two boxes leave the opening).
    let mut slab_lower = lower.clone();
    let mut slab_upper = upper.clone();
    slab_lower[0] = -0.15;
    slab_upper[0] = 0.15;
    slab_upper[1] = 0.3;
    obstacles.push(Obstacle::Cuboid {
        lower: slab_lower,
        upper: slab_upper,
    });
    let centers = [
        [-1.5, -1.0, -1.0, 0.0, 0.0, 0.0, 0.0],
        [1.5, -1.0, -1.0, 0.0, 0.0, 0.0, 0.0],
        [-1.0, 0.5, -0.5, 1.5, 0.5, -1.0, 0.0],
        [1.0, 0.5, -0.5, -1.5, -0.5, 1.0, 0.0],
        [-2.0, -2.0, -2.0, -1.0, 1.0, 2.0, 1.0],
        [2.0, -2.0, -2.0, 1.0, -1.0, -2.0, -1.0],
        [0.0, 1.0, -1.5, 0.0, 0.0, 0.0, 2.0],
        [0.0, -2.0, 0.0, 2.0, 1.0, 0.0, -2.0],
    ];
    for center in centers {
        obstacles.push(Obstacle::Ball {
            center: center.to_vec(),
            radius: 0.9,
        });
    }
    World { space, obstacles }
}
