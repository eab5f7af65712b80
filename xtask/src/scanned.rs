//! The generated, scanned-like objects of `cargo xtask stability` and of the suite's scanned
//! scenes (`crate::suite`, module `scanned`): analytic solids (boxes,
//! bricks, rounded boxes, standing cylinders, soup cans, discs, cone frustums, blobs cut
//! flat) sampled finely (10 000 to 60 000 triangles), every vertex moved by up to 1 mm of
//! seeded uniform noise, placed at a seeded random pose (a scanner's frame, not the object's
//! axes), a third of them written in millimetres. Deterministic: same seed, same bytes.

use anyhow::Context;
use pickplace_geometry::math::{Point3, Real, UnitQuaternion, Vector3};
use pickplace_geometry::mesh::write_stl_binary;
use pickplace_geometry::shapes::{MeshBuilder, ellipsoid_builder, revolve_builder};
use pickplace_objects::{SplitMix64, jittered, subdivided_box_builder};
use std::f64::consts::TAU;
use std::path::{Path, PathBuf};

/// Noise amplitude (m): every coordinate of every vertex moves by up to this much.
pub const NOISE: Real = 0.001;

/// Bump when the generator changes: the files are rewritten when the stamp differs.
const GENERATOR_VERSION: &str = "stability-meshes 1";

/// One generated object file.
#[derive(Debug, Clone)]
pub struct Generated {
    /// Name without extension (`box-03`, `can-02-mm`).
    pub name: String,
    /// The binary STL.
    pub path: PathBuf,
    /// Scale that brings the file to metres (1 or 0.001).
    pub scale: Real,
}

/// A solid before sampling: its kind and a closure building it at a triangle budget.
struct Recipe {
    kind: &'static str,
    build: Box<dyn Fn(usize) -> MeshBuilder>,
}

/// A closed profile for [`revolve_builder`] resampled so that no step exceeds `step` (m).
fn resample(profile: &[[Real; 2]], step: Real) -> Vec<[Real; 2]> {
    let mut out = Vec::new();
    for w in profile.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        let n = (len / step).ceil().max(1.0) as usize;
        for k in 0..n {
            let t = k as Real / n as Real;
            out.push([a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t]);
        }
    }
    out.push(*profile.last().expect("profile"));
    out
}

/// A solid of revolution of `profile` (r, z) with about `triangles` triangles.
pub fn revolved(profile: &[[Real; 2]], triangles: usize) -> MeshBuilder {
    let r_max = profile.iter().map(|p| p[0]).fold(0.0, Real::max);
    let length: Real = profile
        .windows(2)
        .map(|w| ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2)).sqrt())
        .sum();
    // triangles ≈ 2 · (2π r_max / s) · (length / s)
    let step = (2.0 * TAU * r_max * length / triangles as Real).sqrt();
    let segments = (TAU * r_max / step).ceil() as usize;
    revolve_builder(&resample(profile, step), segments)
}

/// A box of full size `size` (base at z = 0) with about `triangles` triangles.
pub fn boxed(size: [Real; 3], triangles: usize) -> MeshBuilder {
    let n = ((triangles as Real / 12.0).sqrt().round() as usize).max(2);
    subdivided_box_builder(size, n)
}

/// A box with edges rounded to `radius`: a subdivided box pushed onto the rounded surface.
pub fn rounded_box(size: [Real; 3], radius: Real, triangles: usize) -> MeshBuilder {
    let mut b = boxed(size, triangles);
    let inner = [
        size[0] / 2.0 - radius,
        size[1] / 2.0 - radius,
        size[2] / 2.0 - radius,
    ];
    for p in &mut b.positions {
        let q = Vector3::new(p.x, p.y, p.z - size[2] / 2.0);
        let c = Vector3::new(
            q.x.clamp(-inner[0], inner[0]),
            q.y.clamp(-inner[1], inner[1]),
            q.z.clamp(-inner[2], inner[2]),
        );
        let d = q - c;
        let n = d.norm();
        let on = if n > 1e-12 { c + d * (radius / n) } else { q };
        *p = Point3::new(on.x, on.y, on.z + size[2] / 2.0);
    }
    b
}

/// An ellipsoid cut flat at `cut` above its lowest point, with a lobed, uneven outline
/// (`lobes` bumps of relative depth `bump` around z, varying with height), ~`triangles`.
pub fn blob(semi: [Real; 3], cut: Real, lobes: u32, bump: Real, triangles: usize) -> MeshBuilder {
    // ellipsoid_builder: ≈ 2 · rings · segments triangles; segments ≈ 2 rings.
    let rings = ((triangles as Real / 4.0).sqrt().round() as usize).max(8);
    let mut b = ellipsoid_builder(semi, cut, rings, 2 * rings);
    let height = 2.0 * semi[2];
    for p in &mut b.positions {
        let a = p.y.atan2(p.x);
        let f = 1.0 + bump * ((lobes as Real) * a + 3.0 * p.z / height).sin();
        // x and y scaled by a factor of the angle and the height only: the cut base stays flat.
        *p = Point3::new(p.x * f, p.y * f, p.z);
    }
    b
}

/// The (r, z) profile of a soup can of radius `r` and height `h`: a rim 3 mm in from the side
/// at both ends, 1.5 mm high (for [`revolved`]).
pub fn can_profile(r: Real, h: Real) -> [[Real; 2]; 8] {
    [
        [0.0, 0.0015],
        [r - 0.003, 0.0015],
        [r - 0.003, 0.0],
        [r, 0.0],
        [r, h],
        [r - 0.003, h],
        [r - 0.003, h - 0.0015],
        [0.0, h - 0.0015],
    ]
}

/// `solid` as a scan sees it: every coordinate of every vertex moved by up to [`NOISE`]
/// (seeded; a vertex shared by triangles moves once, so a closed solid stays closed).
pub fn noisy(solid: MeshBuilder, seed: u64) -> MeshBuilder {
    jittered(solid, NOISE, seed)
}

fn recipes() -> Vec<Recipe> {
    let mut out: Vec<Recipe> = Vec::new();
    let mut add = |kind: &'static str, build: Box<dyn Fn(usize) -> MeshBuilder>| {
        out.push(Recipe { kind, build });
    };
    for size in [
        [0.06, 0.04, 0.10],
        [0.08, 0.08, 0.08],
        [0.12, 0.07, 0.05],
        [0.05, 0.05, 0.15],
        [0.20, 0.14, 0.06],
        [0.09, 0.06, 0.03],
    ] {
        add("box", Box::new(move |t| boxed(size, t)));
    }
    for size in [
        [0.20, 0.06, 0.04],
        [0.15, 0.05, 0.03],
        [0.24, 0.11, 0.07],
        [0.10, 0.03, 0.02],
    ] {
        add("brick", Box::new(move |t| boxed(size, t)));
    }
    for (size, radius) in [
        ([0.08, 0.06, 0.05], 0.008),
        ([0.10, 0.10, 0.04], 0.012),
        ([0.06, 0.05, 0.14], 0.01),
        ([0.15, 0.08, 0.05], 0.02),
        ([0.07, 0.07, 0.07], 0.015),
    ] {
        add(
            "rounded-box",
            Box::new(move |t| rounded_box(size, radius, t)),
        );
    }
    for (r, h) in [(0.025, 0.15), (0.035, 0.20), (0.02, 0.10), (0.04, 0.22)] {
        add(
            "cylinder",
            Box::new(move |t| revolved(&[[0.0, 0.0], [r, 0.0], [r, h], [0.0, h]], t)),
        );
    }
    for (r, h) in [(0.033, 0.12), (0.0425, 0.11), (0.05, 0.07)] {
        // A soup can: a rim 3 mm in from the side at both ends, 1.5 mm high.
        add("can", Box::new(move |t| revolved(&can_profile(r, h), t)));
    }
    for (r, h) in [(0.05, 0.02), (0.07, 0.015)] {
        add(
            "disc",
            Box::new(move |t| revolved(&[[0.0, 0.0], [r, 0.0], [r, h], [0.0, h]], t)),
        );
    }
    for (r0, r1, h) in [
        (0.04, 0.02, 0.10),
        (0.03, 0.045, 0.09),
        (0.05, 0.01, 0.06),
        (0.035, 0.025, 0.15),
    ] {
        add(
            "frustum",
            Box::new(move |t| revolved(&[[0.0, 0.0], [r0, 0.0], [r1, h], [0.0, h]], t)),
        );
    }
    for (semi, cut, lobes, bump) in [
        ([0.04, 0.03, 0.025], 0.006, 3, 0.08),
        ([0.035, 0.035, 0.03], 0.008, 5, 0.05),
        ([0.05, 0.025, 0.02], 0.004, 2, 0.1),
        ([0.03, 0.03, 0.045], 0.01, 4, 0.06),
        ([0.045, 0.04, 0.02], 0.005, 3, 0.12),
        ([0.025, 0.02, 0.03], 0.007, 6, 0.04),
    ] {
        add("blob", Box::new(move |t| blob(semi, cut, lobes, bump, t)));
    }
    out
}

/// Writes the generated objects into `dir` (unless present from this generator version) and
/// returns them.
///
/// # Errors
/// A file that cannot be written.
pub fn generate(dir: &Path, seed: u64) -> anyhow::Result<Vec<Generated>> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let stamp_path = dir.join("VERSION");
    let stamp = format!("{GENERATOR_VERSION} seed {seed}\n");
    let fresh = std::fs::read_to_string(&stamp_path).ok().as_deref() == Some(stamp.as_str());
    let mut counts: std::collections::BTreeMap<&str, usize> = Default::default();
    let mut out = Vec::new();
    for (i, recipe) in recipes().iter().enumerate() {
        let count = counts.entry(recipe.kind).or_default();
        *count += 1;
        let millimetres = i % 3 == 1;
        let name = format!(
            "{}-{:02}{}",
            recipe.kind,
            count,
            if millimetres { "-mm" } else { "" }
        );
        let path = dir.join(format!("{name}.stl"));
        let scale = if millimetres { 0.001 } else { 1.0 };
        if !(fresh && path.is_file()) {
            let mut rng = SplitMix64::new(seed ^ (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
            // A triangle budget between 10 000 and 60 000 (the noise needs a fine sampling).
            let budget = 12_000 + (rng.next_u64() % 44_000) as usize;
            let mut b = noisy((recipe.build)(budget), rng.next_u64());
            // The scanner's frame: a random rotation and an offset of up to 5 cm.
            let axis = Vector3::new(rng.symmetric(), rng.symmetric(), rng.symmetric());
            let rotation = UnitQuaternion::from_scaled_axis(
                axis.normalize() * (rng.symmetric() * std::f64::consts::PI),
            );
            let offset = Vector3::new(rng.symmetric(), rng.symmetric(), rng.symmetric()) * 0.05;
            for p in &mut b.positions {
                *p = (rotation * *p + offset) / scale;
            }
            write_stl_binary(&b, &path).with_context(|| format!("writing {}", path.display()))?;
        }
        out.push(Generated { name, path, scale });
    }
    std::fs::write(&stamp_path, stamp)?;
    Ok(out)
}
