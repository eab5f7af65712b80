//! `cargo xtask suite gen | run`: the scene suite of issue 17.
//!
//! `gen` writes the suite's meshes (`meshes/suite/*.stl`, from the builders of
//! `pickplace_objects`), its scenes (`scenes/suite/*.toml`, NX-HIRO on a table as in
//! the paper's §IV experiments) and its manifest `scenes/suite/suite.toml` (per scene: file,
//! expectation, for infeasible ones the stage and reason the CLI must print, and tags). The
//! output is a pure function of this file: byte-identical on every run, and a test checks that
//! the committed files equal a fresh generation. `run` is in [`crate::suite_run`].

use anyhow::{Context, bail};
use pickplace_geometry::math::{Point3, Real, UnitQuaternion, Vector3};
use pickplace_geometry::mesh::encode_stl_binary;
use pickplace_geometry::shapes::MeshBuilder;
use pickplace_objects as objects;
use std::f64::consts::{FRAC_PI_2, PI};
use std::fmt::Write as _;
use std::path::Path;

mod scans;

/// Height of the table top in the world (m), as in the shipped scenes.
pub const TABLE_TOP: Real = 0.72;

/// The CLI arguments of `cargo xtask suite`.
pub fn run(root: &Path, args: &[String]) -> anyhow::Result<()> {
    match args.first().map(String::as_str) {
        Some("gen") => {
            let files = generate()?;
            for (path, bytes) in &files {
                let full = root.join(path);
                if let Some(parent) = full.parent() {
                    std::fs::create_dir_all(parent)
                        .with_context(|| format!("creating {}", parent.display()))?;
                }
                std::fs::write(&full, bytes).with_context(|| format!("writing {path}"))?;
            }
            write_doc_table(root)?;
            println!(
                "wrote {} files and the table of docs/suite.md: {} scenes in scenes/suite, their meshes in meshes/suite",
                files.len(),
                scenes().len()
            );
            Ok(())
        }
        Some("run") => crate::suite_run::run(root, &args[1..]),
        _ => bail!(
            "usage: cargo xtask suite gen | run [--seeds 1,2,3] [--scenes GLOB] [--write-doc]"
        ),
    }
}

/// A mesh the suite uses: its file relative to the repository root, its geometry, and whether
/// the suite writes it (`false` for the shipped meshes of `meshes/`).
pub struct SuiteMesh {
    pub key: &'static str,
    pub path: &'static str,
    pub builder: MeshBuilder,
    pub written: bool,
    /// The scale that brings the file to metres: 1, or 0.001 for a mesh written in millimetres
    /// (`builder` is in metres either way; the scene says `scale = 0.001`).
    pub scale: Real,
}

/// Every mesh the suite's scenes name, objects first, in a fixed order, then the environment,
/// then the scanned-like objects of [`scans`].
pub fn meshes() -> Vec<SuiteMesh> {
    let mut all = suite_meshes();
    all.extend(scans::meshes());
    all
}

fn suite_meshes() -> Vec<SuiteMesh> {
    let suite = |key, path, builder| SuiteMesh {
        key,
        path,
        builder,
        written: true,
        scale: 1.0,
    };
    let shipped = |key, path, builder| SuiteMesh {
        key,
        path,
        builder,
        written: false,
        scale: 1.0,
    };
    vec![
        // Objects.
        shipped("can", "meshes/can.stl", objects::can_builder()),
        shipped("mug", "meshes/mug.stl", objects::mug_builder()),
        shipped("box", "meshes/box.stl", objects::object_box_builder()),
        suite(
            "cereal",
            "meshes/suite/cereal-box.stl",
            objects::cereal_box_builder(),
        ),
        suite(
            "domino",
            "meshes/suite/domino.stl",
            objects::domino_builder(),
        ),
        suite(
            "block",
            "meshes/suite/toy-block.stl",
            objects::toy_block_builder(),
        ),
        suite(
            "carton",
            "meshes/suite/milk-carton.stl",
            objects::milk_carton_builder(),
        ),
        suite(
            "dense-can",
            "meshes/suite/dense-can.stl",
            objects::dense_can_builder(),
        ),
        suite(
            "bottle",
            "meshes/suite/bottle.stl",
            objects::punted_bottle_builder(),
        ),
        suite(
            "l-shape",
            "meshes/suite/l-shape.stl",
            objects::l_shape_builder(),
        ),
        suite(
            "brick",
            "meshes/suite/hollow-brick.stl",
            objects::hollow_brick_builder(),
        ),
        suite("fruit", "meshes/suite/fruit.stl", objects::fruit_builder()),
        suite("duck", "meshes/suite/duck.stl", objects::duck_builder()),
        suite(
            "scanned-box",
            "meshes/suite/scanned-box.stl",
            objects::scanned_box_builder(),
        ),
        suite(
            "big-cube",
            "meshes/suite/big-cube.stl",
            objects::box_on_base_builder([0.10, 0.10, 0.10]),
        ),
        // Environment.
        suite(
            "table",
            "meshes/suite/table.stl",
            objects::plain_table_builder([0.6, 0.9], 0.70),
        ),
        shipped("pallet", "meshes/pallet.stl", objects::pallet_builder()),
        suite(
            "shelf",
            "meshes/suite/shelf.stl",
            objects::shelf_builder([0.20, 0.30], 0.15),
        ),
        suite(
            "wall",
            "meshes/suite/wall.stl",
            objects::box_on_base_builder([0.02, 0.40, 0.25]),
        ),
        suite(
            "block-tall",
            "meshes/suite/gap-block.stl",
            objects::box_on_base_builder([0.10, 0.05, 0.06]),
        ),
        suite(
            "obstacle",
            "meshes/suite/obstacle.stl",
            objects::box_on_base_builder([0.06, 0.06, 0.12]),
        ),
        suite(
            "low-box",
            "meshes/suite/low-box.stl",
            objects::box_on_base_builder([0.10, 0.06, 0.05]),
        ),
        suite("ramp", "meshes/suite/ramp.stl", ramp_builder()),
    ]
}

/// A 45° ramp: a wedge 0.12 m long (x), 0.15 m wide (y) and 0.12 m high, rising towards −x.
/// No object stays on it without friction the planner does not model (a target on it is
/// infeasible).
fn ramp_builder() -> MeshBuilder {
    objects::extruded_builder(&[[-0.06, 0.0], [0.06, 0.0], [-0.06, 0.12]], 0, 0.15)
}

/// How the object starts: on its base, on its side, upside down (a rotation applied before
/// the yaw about the vertical).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Tilt {
    Upright,
    /// 90° about x, after a turn of `roll` about the object's own z (a facet of a prism down).
    OnSide {
        roll: Real,
    },
    /// 90° about y.
    OnEnd,
    /// 180° about x.
    UpsideDown,
}

/// What the suite expects of a scene.
#[derive(Debug, Clone, PartialEq)]
pub enum Expect {
    Feasible,
    /// `pickplace plan` exits 1 and its stderr contains `stage` and `reason` (any case).
    Infeasible {
        stage: &'static str,
        reason: &'static str,
    },
}

/// One environment part: a mesh key, a unique name, where it stands (its base's centre) and
/// its yaw.
#[derive(Debug, Clone)]
pub struct Part {
    pub name: &'static str,
    pub mesh: &'static str,
    pub at: [Real; 3],
    pub yaw: Real,
}

/// One scene of the suite.
#[derive(Debug, Clone)]
pub struct Spec {
    pub name: &'static str,
    pub about: &'static str,
    pub object: &'static str,
    pub tilt: Tilt,
    pub yaw: Real,
    /// Centre of the object's footprint (x, y) and the height of the support under it.
    pub start: [Real; 3],
    /// Added to the resting height: > 0 floats, < 0 penetrates.
    pub lift: Real,
    pub parts: Vec<Part>,
    pub target: [Real; 3],
    pub start_state: Vec<(&'static str, Real)>,
    /// `Some("")` disables an arm (a one-armed robot).
    pub left_arm: Option<&'static str>,
    pub right_arm: Option<&'static str>,
    pub tags: Vec<&'static str>,
    pub expect: Expect,
    /// A feasible scene the planner does not meet yet, and why: listed as open by
    /// `cargo xtask suite run`, which then does not fail on it (issue 17 is open while any
    /// scene is).
    pub open: Option<&'static str>,
}

fn table() -> Part {
    Part {
        name: "table",
        mesh: "table",
        at: [0.55, 0.0, TABLE_TOP - 0.70],
        yaw: 0.0,
    }
}

fn part(name: &'static str, mesh: &'static str, x: Real, y: Real) -> Part {
    Part {
        name,
        mesh,
        at: [x, y, TABLE_TOP],
        yaw: 0.0,
    }
}

/// The pallet of the paper's Fig. 9 at `(x, y)` on the table, and the world points of the
/// floors of its dents: large (0.09 square, 15 mm), small (0.05 square, 10 mm), pocket
/// (0.075 × 0.12, 20 mm), groove (0.16 × 0.04, 12 mm).
fn pallet(x: Real, y: Real) -> (Part, [[Real; 3]; 4]) {
    let top = TABLE_TOP + objects::PALLET_SIZE[2];
    let d = objects::PALLET_DENTS;
    let floor = |i: usize| [x + d[i].center[0], y + d[i].center[1], top - d[i].depth];
    (
        part("pallet", "pallet", x, y),
        [floor(0), floor(1), floor(2), floor(3)],
    )
}

/// Two blocks (0.10 × 0.05 × 0.06, lower than the objects put between them, so that a hand from above clears them) whose inner faces are `gap` apart across y, centred at
/// `(x, y)`.
fn gap_blocks(x: Real, y: Real, gap: Real) -> [Part; 2] {
    let off = gap / 2.0 + 0.025;
    [
        part("gap-block-a", "block-tall", x, y - off),
        part("gap-block-b", "block-tall", x, y + off),
    ]
}

/// The shelf (board 0.20 × 0.30, top 0.15 m above the table) at `(x, y)`, and the point on its
/// board's centre.
fn shelf(x: Real, y: Real) -> (Part, [Real; 3]) {
    (part("shelf", "shelf", x, y), [x, y, TABLE_TOP + 0.15])
}

/// A feasible scene on the table: `object` upright from `start` (on the table) to `target`,
/// both arms.
fn base(
    name: &'static str,
    about: &'static str,
    object: &'static str,
    start: [Real; 2],
    target: [Real; 3],
) -> Spec {
    Spec {
        name,
        about,
        object,
        tilt: Tilt::Upright,
        yaw: 0.0,
        start: [start[0], start[1], TABLE_TOP],
        lift: 0.0,
        parts: vec![table()],
        target,
        start_state: Vec::new(),
        left_arm: None,
        right_arm: None,
        tags: Vec::new(),
        expect: Expect::Feasible,
        open: None,
    }
}

/// The point `(x, y)` on the table top.
fn on_table(x: Real, y: Real) -> [Real; 3] {
    [x, y, TABLE_TOP]
}

/// Every scene, in the manifest's order: the suite's own, then the scanned-like objects'
/// of [`scans`].
pub fn scenes() -> Vec<Spec> {
    let mut all = suite_scenes();
    all.extend(scans::scenes());
    all
}

fn suite_scenes() -> Vec<Spec> {
    let side64 = Tilt::OnSide { roll: PI / 64.0 };
    let mut s = Vec::new();

    // --- Single arm, table to table.
    let mut sc = base(
        "can-right",
        "a can near the right hand moved along the table",
        "can",
        [0.40, -0.22],
        on_table(0.48, -0.08),
    );
    sc.tags = vec!["table", "right"];
    s.push(sc);
    let mut sc = base(
        "can-left",
        "a can near the left hand moved along the table",
        "can",
        [0.40, 0.22],
        on_table(0.48, 0.08),
    );
    sc.tags = vec!["table", "left"];
    s.push(sc);
    let mut sc = base(
        "cereal-box-right",
        "the 3 cm deep cereal box of issue 17, standing, its narrow side to the robot",
        "cereal",
        [0.54, -0.20],
        on_table(0.42, -0.02),
    );
    sc.tags = vec!["table", "thin"];
    s.push(sc);
    let mut sc = base(
        "cereal-box-left-turned",
        "the cereal box turned 60° on the table",
        "cereal",
        [0.50, 0.20],
        on_table(0.40, 0.03),
    );
    sc.yaw = PI / 3.0;
    sc.tags = vec!["table", "thin"];
    s.push(sc);
    let mut sc = base(
        "carton-right",
        "a gable-top milk carton moved along the table",
        "carton",
        [0.50, -0.18],
        on_table(0.42, -0.03),
    );
    sc.tags = vec!["table"];
    s.push(sc);
    let mut sc = base(
        "domino-on-end",
        "a domino standing on its end (24 x 7.5 mm base)",
        "domino",
        [0.40, -0.15],
        on_table(0.46, -0.02),
    );
    sc.tilt = Tilt::OnEnd;
    sc.tags = vec!["table", "thin", "on-side"];
    s.push(sc);
    let mut sc = base(
        "block-left",
        "a 4 cm toy block near the left hand",
        "block",
        [0.38, 0.18],
        on_table(0.46, 0.05),
    );
    sc.tags = vec!["table", "left"];
    s.push(sc);
    let mut sc = base(
        "brick-right",
        "a hollow open box with 2 mm walls",
        "brick",
        [0.40, -0.20],
        on_table(0.47, -0.06),
    );
    sc.tags = vec!["table", "thin-walled"];
    s.push(sc);
    let mut sc = base(
        "fruit-left",
        "a doubly curved fruit",
        "fruit",
        [0.40, 0.20],
        on_table(0.46, 0.06),
    );
    sc.tags = vec!["table", "curved"];
    s.push(sc);
    let mut sc = base(
        "duck-right",
        "a rubber duck (body and head, doubly curved)",
        "duck",
        [0.40, -0.20],
        on_table(0.47, -0.06),
    );
    sc.tags = vec!["table", "curved"];
    s.push(sc);
    let mut sc = base(
        "l-shape-right",
        "an L-shaped block standing on its foot",
        "l-shape",
        [0.50, -0.20],
        on_table(0.42, -0.05),
    );
    sc.tags = vec!["table"];
    s.push(sc);
    let mut sc = base(
        "dense-can-right",
        "a can of 6656 sliver triangles",
        "dense-can",
        [0.40, -0.20],
        on_table(0.48, -0.06),
    );
    sc.tags = vec!["table", "thousands-of-triangles"];
    s.push(sc);
    let mut sc = base(
        "scanned-box-left",
        "a scanned-looking box (3072 noisy triangles)",
        "scanned-box",
        [0.40, 0.20],
        on_table(0.48, 0.06),
    );
    sc.tags = vec!["table", "thousands-of-triangles"];
    s.push(sc);
    let mut sc = base(
        "bottle-right",
        "a bottle with a punted base and a neck",
        "bottle",
        [0.50, -0.20],
        on_table(0.42, -0.04),
    );
    sc.tags = vec!["table", "punted"];
    s.push(sc);

    // --- On the side, upside down.
    let mut sc = base(
        "bottle-on-side",
        "a bottle lying on its side, set down anywhere near the target",
        "bottle",
        [0.42, -0.18],
        on_table(0.46, -0.02),
    );
    sc.tilt = side64;
    sc.yaw = FRAC_PI_2;
    sc.tags = vec!["table", "on-side", "punted"];
    s.push(sc);
    let mut sc = base(
        "carton-on-side",
        "a milk carton lying on its side",
        "carton",
        [0.50, -0.18],
        on_table(0.44, -0.02),
    );
    sc.tilt = Tilt::OnSide { roll: 0.0 };
    sc.yaw = FRAC_PI_2;
    sc.tags = vec!["table", "on-side"];
    s.push(sc);
    let mut sc = base(
        "l-shape-on-side",
        "an L-shaped block lying on its L face",
        "l-shape",
        [0.42, 0.18],
        on_table(0.46, 0.02),
    );
    sc.tilt = Tilt::OnSide { roll: 0.0 };
    sc.tags = vec!["table", "on-side"];
    s.push(sc);
    let mut sc = base(
        "mug-upside-down",
        "a mug standing upside down on its rim: its 8 cm body leaves no room in NX-HIRO's 8 cm opening and the rim is against the table, so the hand pinches its handle across the tube (the pads wrap the curved tube)",
        "mug",
        [0.40, -0.18],
        on_table(0.47, -0.03),
    );
    sc.tilt = Tilt::UpsideDown;
    sc.tags = vec!["table", "upside-down", "curved"];
    s.push(sc);
    let mut sc = base(
        "scanned-box-on-side",
        "the scanned box lying on a long side",
        "scanned-box",
        [0.42, -0.18],
        on_table(0.47, -0.04),
    );
    sc.tilt = Tilt::OnSide { roll: 0.0 };
    sc.yaw = FRAC_PI_2;
    sc.tags = vec!["table", "on-side", "thousands-of-triangles"];
    s.push(sc);
    let mut sc = base(
        "dense-can-upside-down",
        "the dense can upside down",
        "dense-can",
        [0.40, 0.20],
        on_table(0.46, 0.05),
    );
    sc.tilt = Tilt::UpsideDown;
    sc.tags = vec!["table", "upside-down", "thousands-of-triangles"];
    s.push(sc);

    // --- Dents.
    let (p, dents) = pallet(0.48, -0.20);
    let mut sc = base(
        "can-into-large-dent",
        "a can into the pallet's large dent (Fig. 9, pallet moved)",
        "can",
        [0.38, 0.02],
        dents[0],
    );
    sc.parts.push(p.clone());
    sc.tags = vec!["dent"];
    s.push(sc);
    // The pocket and the small dent of the pallet where the Fig. 9 scenes have it are at the
    // edge of NX-HIRO's right arm: its tool point gets to the box's grasp centre in the pocket
    // (0.59, -0.25, 0.83) in none of 3 million seeded random configurations (within 1 cm),
    // and to the block's in the small dent (0.53, -0.14, 0.78) in 10, none pointing within
    // 25° of the downward approaches that alone fit there (the closed gripper of every other
    // grasp hits the pallet); IK with 300 restarts fails on every grasp that fits. The left
    // arm does not reach y < -0.1 there. So both are refused at the place ("no IK"), and
    // the same jobs with the pallet 10 cm nearer are feasible scenes.
    let mut sc = base(
        "box-into-pocket",
        "the box object into the pallet's deep pocket at x = 0.61 m, beyond the right hand's workspace for the box's low grasps",
        "box",
        [0.38, 0.02],
        dents[2],
    );
    sc.parts.push(p.clone());
    sc.tags = vec!["dent", "no-solution"];
    sc.expect = Expect::Infeasible {
        stage: "place",
        reason: "no IK",
    };
    s.push(sc);
    let mut sc = base(
        "block-into-small-dent",
        "a 4 cm toy block into the 5 cm dent at x = 0.53 m, where no downward approach of the right hand reaches",
        "block",
        [0.38, 0.02],
        dents[1],
    );
    sc.parts.push(p.clone());
    sc.tags = vec!["dent", "no-solution"];
    sc.expect = Expect::Infeasible {
        stage: "place",
        reason: "no IK",
    };
    s.push(sc);
    let (near, near_dents) = pallet(0.38, -0.20);
    let mut sc = base(
        "box-into-pocket-near",
        "the box object into the pallet's deep pocket, the pallet 10 cm nearer (pocket at x = 0.51 m)",
        "box",
        [0.38, 0.02],
        near_dents[2],
    );
    sc.parts.push(near.clone());
    sc.tags = vec!["dent"];
    s.push(sc);
    let mut sc = base(
        "block-into-small-dent-near",
        "a 4 cm toy block into the 5 cm dent, the pallet 10 cm nearer (dent at x = 0.43 m)",
        "block",
        [0.38, 0.02],
        near_dents[1],
    );
    sc.parts.push(near);
    sc.tags = vec!["dent"];
    s.push(sc);
    let mut sc = base(
        "brick-into-large-dent",
        "the hollow brick into the large dent",
        "brick",
        [0.38, 0.02],
        dents[0],
    );
    sc.parts.push(p.clone());
    sc.tags = vec!["dent", "thin-walled"];
    s.push(sc);

    // --- Shelves.
    let (sh, top) = shelf(0.55, -0.20);
    let mut sc = base(
        "box-onto-shelf",
        "the box object onto a shelf board 15 cm above the table",
        "box",
        [0.38, 0.0],
        top,
    );
    sc.parts.push(sh.clone());
    sc.tags = vec!["shelf"];
    s.push(sc);
    let mut sc = base(
        "bottle-onto-shelf",
        "the punted bottle onto the shelf",
        "bottle",
        [0.38, 0.0],
        top,
    );
    sc.parts.push(sh.clone());
    sc.tags = vec!["shelf", "punted"];
    s.push(sc);
    let mut sc = base(
        "mug-onto-shelf",
        "the mug onto the shelf",
        "mug",
        [0.38, 0.0],
        top,
    );
    sc.parts.push(sh.clone());
    sc.tags = vec!["shelf"];
    s.push(sc);
    let (shl, topl) = shelf(0.55, 0.20);
    let mut sc = base(
        "carton-onto-left-shelf",
        "a milk carton onto a shelf on the left",
        "carton",
        [0.38, 0.0],
        topl,
    );
    sc.parts.push(shl);
    sc.tags = vec!["shelf", "left"];
    s.push(sc);
    let mut sc = base(
        "scanned-box-onto-shelf",
        "the scanned box onto the shelf",
        "scanned-box",
        [0.38, 0.0],
        top,
    );
    sc.parts.push(sh);
    sc.tags = vec!["shelf", "thousands-of-triangles"];
    s.push(sc);

    // --- Narrow gaps (7 cm between two 6 cm blocks).
    let gap_target = on_table(0.48, -0.18);
    let mut sc = base(
        "can-into-gap",
        "a can (6.6 cm) into a 7 cm gap between two blocks",
        "can",
        [0.38, 0.05],
        gap_target,
    );
    sc.parts.extend(gap_blocks(0.48, -0.18, 0.07));
    sc.tags = vec!["gap"];
    s.push(sc);
    let mut sc = base(
        "box-into-gap",
        "the box object upright into the 7 cm gap",
        "box",
        [0.38, 0.05],
        gap_target,
    );
    sc.parts.extend(gap_blocks(0.48, -0.18, 0.07));
    sc.tags = vec!["gap"];
    s.push(sc);
    let mut sc = base(
        "cereal-box-into-gap",
        "the cereal box standing into the 7 cm gap",
        "cereal",
        [0.50, 0.08],
        gap_target,
    );
    sc.yaw = FRAC_PI_2;
    sc.parts.extend(gap_blocks(0.48, -0.18, 0.07));
    sc.tags = vec!["gap", "thin"];
    s.push(sc);
    let mut sc = base(
        "dense-can-into-gap",
        "the dense can into the 7 cm gap",
        "dense-can",
        [0.38, 0.05],
        gap_target,
    );
    sc.parts.extend(gap_blocks(0.48, -0.18, 0.07));
    sc.tags = vec!["gap", "thousands-of-triangles"];
    s.push(sc);

    // --- Clutter around the start and the target.
    let mut sc = base(
        "can-clutter-start",
        "a can boxed in by three obstacles, to an open spot",
        "can",
        [0.42, -0.20],
        on_table(0.45, 0.0),
    );
    sc.parts.extend([
        part("obstacle-a", "obstacle", 0.52, -0.20),
        part("obstacle-b", "obstacle", 0.42, -0.30),
        part("obstacle-c", "low-box", 0.42, -0.10),
    ]);
    sc.tags = vec!["clutter"];
    s.push(sc);
    let mut sc = base(
        "mug-clutter-target",
        "a mug to a spot among three obstacles (Fig. 10(b) kind)",
        "mug",
        [0.38, 0.05],
        on_table(0.46, -0.22),
    );
    sc.parts.extend([
        part("obstacle-a", "obstacle", 0.57, -0.22),
        part("obstacle-b", "obstacle", 0.46, -0.34),
        part("obstacle-c", "low-box", 0.36, -0.22),
    ]);
    sc.tags = vec!["clutter"];
    s.push(sc);
    let mut sc = base(
        "bottle-before-wall",
        "a bottle set down 8 cm in front of a wall",
        "bottle",
        [0.40, 0.0],
        on_table(0.50, -0.15),
    );
    sc.parts.push(part("wall", "wall", 0.60, -0.15));
    sc.tags = vec!["clutter", "punted"];
    s.push(sc);
    let mut sc = base(
        "cereal-box-clutter-both",
        "the cereal box from among obstacles to a spot before a wall",
        "cereal",
        [0.50, -0.22],
        on_table(0.44, 0.02),
    );
    sc.yaw = FRAC_PI_2;
    sc.parts.extend([
        part("obstacle-a", "obstacle", 0.50, -0.36),
        part("obstacle-b", "low-box", 0.60, -0.22),
        part("obstacle-c", "low-box", 0.50, -0.06),
        part("wall", "wall", 0.58, 0.02),
    ]);
    sc.tags = vec!["clutter", "thin"];
    s.push(sc);

    // --- Handovers: start far on one side, target far on the other.
    let mut sc = base(
        "can-handover-left-to-right",
        "a can from far left to far right",
        "can",
        [0.46, 0.34],
        on_table(0.44, -0.34),
    );
    sc.tags = vec!["handover"];
    s.push(sc);
    let mut sc = base(
        "box-handover-right-to-left",
        "the box object from far right to far left",
        "box",
        [0.46, -0.34],
        on_table(0.44, 0.34),
    );
    sc.tags = vec!["handover"];
    s.push(sc);
    let mut sc = base(
        "duck-handover",
        "the duck from far left to far right",
        "duck",
        [0.46, 0.34],
        on_table(0.44, -0.34),
    );
    sc.tags = vec!["handover", "curved"];
    s.push(sc);
    let (p, dents) = pallet(0.48, -0.22);
    let mut sc = base(
        "carton-handover-into-pocket",
        "a milk carton from far left into the pallet's pocket on the right",
        "carton",
        [0.46, 0.34],
        dents[2],
    );
    sc.parts.push(p);
    sc.tags = vec!["handover", "dent"];
    s.push(sc);

    // --- Regrasp: one arm, lying box, upright only into the gap.
    let mut sc = base(
        "box-on-side-into-gap-right-arm-only",
        "one arm: the box lies on its side; only upright does it fit the gap, and no grasp that picks it lying places it upright, so it is put down upright and picked again",
        "box",
        [0.40, -0.02],
        gap_target,
    );
    sc.tilt = Tilt::OnSide { roll: 0.0 };
    sc.yaw = FRAC_PI_2;
    sc.parts.extend(gap_blocks(0.48, -0.18, 0.07));
    sc.left_arm = Some("");
    sc.tags = vec!["regrasp", "gap", "on-side"];
    s.push(sc);
    let mut sc = base(
        "box-on-side-into-gap-left-arm-only",
        "the same, mirrored, with the left arm only",
        "box",
        [0.40, 0.02],
        on_table(0.48, 0.18),
    );
    sc.tilt = Tilt::OnSide { roll: 0.0 };
    sc.yaw = FRAC_PI_2;
    sc.parts.extend(gap_blocks(0.48, 0.18, 0.07));
    sc.right_arm = Some("");
    sc.tags = vec!["regrasp", "gap", "on-side"];
    s.push(sc);
    let mut sc = base(
        "scanned-box-on-side-into-gap-right-arm-only",
        "one arm: the scanned box lying, upright into the gap",
        "scanned-box",
        [0.40, -0.02],
        gap_target,
    );
    sc.tilt = Tilt::OnSide { roll: 0.0 };
    sc.yaw = FRAC_PI_2;
    sc.parts.extend(gap_blocks(0.48, -0.18, 0.07));
    sc.left_arm = Some("");
    sc.tags = vec!["regrasp", "gap", "on-side", "thousands-of-triangles"];
    s.push(sc);

    // --- No solution.
    let infeasible = |stage, reason| Expect::Infeasible { stage, reason };
    let mut sc = base(
        "target-out-of-reach",
        "the target on a second table 1.2 m in front: no hand reaches it",
        "can",
        [0.40, -0.20],
        on_table(1.35, -0.10),
    );
    sc.parts.push(Part {
        name: "far-table",
        mesh: "table",
        at: [1.45, 0.0, TABLE_TOP - 0.70],
        yaw: 0.0,
    });
    sc.tags = vec!["no-solution"];
    sc.expect = infeasible("place", "out of reach");
    s.push(sc);
    let mut sc = base(
        "big-cube-no-grasp",
        "a 10 cm cube: wider than the 8 cm opening every way",
        "big-cube",
        [0.42, -0.20],
        on_table(0.46, -0.02),
    );
    sc.tags = vec!["no-solution"];
    sc.expect = infeasible("grasp", "no grasp");
    s.push(sc);
    let mut sc = base(
        "can-into-narrow-gap",
        "a can (6.6 cm) into a 5 cm gap",
        "can",
        [0.38, 0.05],
        gap_target,
    );
    sc.parts.extend(gap_blocks(0.48, -0.18, 0.05));
    sc.tags = vec!["no-solution", "gap"];
    sc.expect = infeasible("placement", "no stable placement");
    s.push(sc);
    let mut sc = base(
        "start-in-collision",
        "the right hand starts 1.6 cm inside the table top (shoulder and elbow pitched down)",
        "can",
        [0.42, 0.10],
        on_table(0.46, 0.0),
    );
    sc.start_state = vec![("RARM_JOINT1", -0.4), ("RARM_JOINT2", -0.9)];
    sc.tags = vec!["no-solution"];
    sc.expect = infeasible("start state", "in collision");
    s.push(sc);
    let mut sc = base(
        "object-floating",
        "the can 5 cm above the table",
        "can",
        [0.45, 0.0],
        on_table(0.46, -0.15),
    );
    sc.lift = 0.05;
    sc.tags = vec!["no-solution"];
    sc.expect = infeasible("object", "not resting");
    s.push(sc);
    let mut sc = base(
        "object-in-table",
        "the can 1 cm into the table",
        "can",
        [0.45, 0.0],
        on_table(0.46, -0.15),
    );
    sc.lift = -0.01;
    sc.tags = vec!["no-solution"];
    sc.expect = infeasible("object", "penetrat");
    s.push(sc);
    let mut sc = base(
        "target-in-mid-air",
        "the target 15 cm above the table, on nothing",
        "can",
        [0.42, -0.20],
        [0.46, -0.02, TABLE_TOP + 0.15],
    );
    sc.tags = vec!["no-solution"];
    sc.expect = infeasible("target", "not on any surface");
    s.push(sc);
    let mut sc = base(
        "target-on-ramp",
        "the target on a 45° ramp, where nothing stays without friction",
        "box",
        [0.40, 0.10],
        [0.46, -0.20, TABLE_TOP + 0.06],
    );
    sc.parts.push(part("ramp", "ramp", 0.46, -0.20));
    sc.tags = vec!["no-solution"];
    sc.expect = infeasible("target", "too steep");
    s.push(sc);
    s
}

/// The world-from-object rotation of a tilt and a yaw.
fn rotation(tilt: Tilt, yaw: Real) -> UnitQuaternion {
    let z = Vector3::z_axis();
    let tilt = match tilt {
        Tilt::Upright => UnitQuaternion::identity(),
        Tilt::OnSide { roll } => {
            UnitQuaternion::from_axis_angle(&Vector3::x_axis(), FRAC_PI_2)
                * UnitQuaternion::from_axis_angle(&z, roll)
        }
        Tilt::OnEnd => UnitQuaternion::from_axis_angle(&Vector3::y_axis(), FRAC_PI_2),
        Tilt::UpsideDown => UnitQuaternion::from_axis_angle(&Vector3::x_axis(), PI),
    };
    UnitQuaternion::from_axis_angle(&z, yaw) * tilt
}

/// Rounds to 0.1 µm so that the text is short and stable (`-0.0` as `0`).
fn r(v: Real) -> Real {
    let x = (v * 1e7).round() / 1e7;
    if x == 0.0 { 0.0 } else { x }
}

fn fmt3(v: [Real; 3]) -> String {
    format!("[{}, {}, {}]", r(v[0]), r(v[1]), r(v[2]))
}

fn fmt_q(q: &UnitQuaternion) -> String {
    // ROS order, with w ≥ 0 so that the text is unique.
    let c = q.coords;
    let s = if c.w < 0.0 { -1.0 } else { 1.0 };
    format!(
        "[{}, {}, {}, {}]",
        r(s * c.x),
        r(s * c.y),
        r(s * c.z),
        r(s * c.w)
    )
}

/// The object's start pose: the rotation of the spec, then the translation that puts the
/// centre of its rotated bounding box over `start` and its lowest point on the support
/// (plus `lift`). The lowest point is computed after rounding the rotation as written, so
/// that a resting object rests to 0.1 µm.
fn start_pose(spec: &Spec, mesh: &MeshBuilder) -> ([Real; 3], UnitQuaternion) {
    let q = rotation(spec.tilt, spec.yaw);
    let mut lo = Vector3::repeat(Real::INFINITY);
    let mut hi = Vector3::repeat(Real::NEG_INFINITY);
    for p in &mesh.positions {
        let w: Point3 = q * p;
        lo = lo.inf(&w.coords);
        hi = hi.sup(&w.coords);
    }
    let c = (lo + hi) / 2.0;
    (
        [
            spec.start[0] - c.x,
            spec.start[1] - c.y,
            spec.start[2] - lo.z + spec.lift,
        ],
        q,
    )
}

/// The scene file of a spec.
fn scene_toml(spec: &Spec, meshes: &[SuiteMesh]) -> anyhow::Result<String> {
    let mesh = |key: &str| {
        meshes
            .iter()
            .find(|m| m.key == key)
            .with_context(|| format!("scene {}: no mesh {key}", spec.name))
    };
    let object = mesh(spec.object)?;
    let (position, q) = start_pose(spec, &object.builder);
    let mut t = String::new();
    writeln!(
        t,
        "# Scene suite (issue 17), generated by `cargo xtask suite gen`: do not edit."
    )?;
    writeln!(t, "# {}: {}.", spec.name, spec.about)?;
    match &spec.expect {
        Expect::Feasible => writeln!(t, "# Expected: feasible.")?,
        Expect::Infeasible { stage, reason } => writeln!(
            t,
            "# Expected: no solution; `pickplace plan` exits 1 naming {stage:?} and {reason:?}."
        )?,
    }
    writeln!(t, "format = 1\n")?;
    writeln!(t, "[robot]")?;
    writeln!(t, "urdf = \"../../robots/nx-hiro/nx-hiro.urdf\"")?;
    writeln!(t, "srdf = \"../../robots/nx-hiro/nx-hiro.srdf\"")?;
    writeln!(t, "gripper = \"../../robots/nx-hiro/gripper.toml\"")?;
    writeln!(t, "base_pose = {{ position = [0.0, 0.0, 0.92] }}")?;
    if !spec.start_state.is_empty() {
        let joints: Vec<String> = spec
            .start_state
            .iter()
            .map(|(j, v)| format!("{j} = {}", r(*v)))
            .collect();
        writeln!(t, "start_state = {{ {} }}", joints.join(", "))?;
    }
    writeln!(t, "\n[object]")?;
    writeln!(t, "mesh = \"../../{}\"", object.path)?;
    if object.scale != 1.0 {
        writeln!(t, "scale = {}", object.scale)?;
    }
    writeln!(
        t,
        "start_pose = {{ position = {}, orientation = {} }}",
        fmt3(position),
        fmt_q(&q)
    )?;
    for p in &spec.parts {
        let m = mesh(p.mesh)?;
        let q = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), p.yaw);
        writeln!(t, "\n[[environment]]")?;
        writeln!(t, "name = \"{}\"", p.name)?;
        writeln!(t, "mesh = \"../../{}\"", m.path)?;
        writeln!(
            t,
            "pose = {{ position = {}, orientation = {} }}",
            fmt3(p.at),
            fmt_q(&q)
        )?;
    }
    writeln!(t, "\n[target]")?;
    writeln!(t, "point = {}", fmt3(spec.target))?;
    writeln!(t, "\n[planner]")?;
    writeln!(t, "seed = 1")?;
    if let Some(a) = spec.right_arm {
        writeln!(t, "right_arm = \"{a}\"")?;
    }
    if let Some(a) = spec.left_arm {
        writeln!(t, "left_arm = \"{a}\"")?;
    }
    Ok(t)
}

/// The manifest `scenes/suite/suite.toml`.
fn manifest(specs: &[Spec]) -> anyhow::Result<String> {
    let mut t = String::new();
    writeln!(
        t,
        "# The scene suite of issue 17, generated by `cargo xtask suite gen`: do not edit."
    )?;
    writeln!(
        t,
        "# `cargo xtask suite run` plans every scene with seeds 1 to 3 and checks each"
    )?;
    writeln!(t, "# expectation (docs/suite.md).")?;
    writeln!(t, "format = 1")?;
    for s in specs {
        writeln!(t, "\n[[scene]]")?;
        writeln!(t, "name = \"{}\"", s.name)?;
        writeln!(t, "file = \"{}.toml\"", s.name)?;
        writeln!(t, "object = \"{}\"", s.object)?;
        match &s.expect {
            Expect::Feasible => writeln!(t, "expect = \"feasible\"")?,
            Expect::Infeasible { stage, reason } => {
                writeln!(t, "expect = \"infeasible\"")?;
                writeln!(t, "stage = \"{stage}\"")?;
                writeln!(t, "reason = \"{reason}\"")?;
            }
        }
        if let Some(open) = s.open {
            writeln!(t, "open = \"{}\"", open.replace('"', "'"))?;
        }
        let tags: Vec<String> = s.tags.iter().map(|t| format!("\"{t}\"")).collect();
        writeln!(t, "tags = [{}]", tags.join(", "))?;
        writeln!(t, "about = \"{}\"", s.about.replace('"', "'"))?;
    }
    Ok(t)
}

/// Opening marker of the generated table in `docs/suite.md`.
pub const TABLE_BEGIN: &str = "<!-- xtask suite gen: begin -->";
/// Closing marker.
pub const TABLE_END: &str = "<!-- xtask suite gen: end -->";

/// The table of scenes of `docs/suite.md` (between the markers).
pub fn doc_table() -> anyhow::Result<String> {
    let mut t = String::new();
    writeln!(t, "| scene | object | start | expected | tags | what |")?;
    writeln!(t, "|---|---|---|---|---|---|")?;
    for s in scenes() {
        let start = match s.tilt {
            Tilt::Upright => "upright",
            Tilt::OnSide { .. } => "on its side",
            Tilt::OnEnd => "on its end",
            Tilt::UpsideDown => "upside down",
        };
        let expect = match &s.expect {
            Expect::Feasible => "feasible".to_owned(),
            Expect::Infeasible { stage, reason } => format!("exit 1: {stage} / {reason}"),
        };
        writeln!(
            t,
            "| `{}` | {} | {start} | {expect} | {} | {} |",
            s.name,
            s.object,
            s.tags.join(", "),
            s.about
        )?;
    }
    Ok(t)
}

/// `docs/suite.md` with its table replaced by a fresh [`doc_table`].
pub fn doc_with_table(doc: &str) -> anyhow::Result<String> {
    let (b, e) = match (doc.find(TABLE_BEGIN), doc.find(TABLE_END)) {
        (Some(b), Some(e)) if b < e => (b + TABLE_BEGIN.len(), e),
        _ => bail!("docs/suite.md: {TABLE_BEGIN} … {TABLE_END} not found"),
    };
    Ok(format!("{}\n{}{}", &doc[..b], doc_table()?, &doc[e..]))
}

fn write_doc_table(root: &Path) -> anyhow::Result<()> {
    let path = root.join("docs/suite.md");
    let doc = std::fs::read_to_string(&path).with_context(|| format!("{}", path.display()))?;
    std::fs::write(&path, doc_with_table(&doc)?).with_context(|| format!("{}", path.display()))
}

/// Every file of the suite, as (path relative to the repository root, bytes), in a fixed
/// order: the written meshes, the scenes, the manifest.
pub fn generate() -> anyhow::Result<Vec<(String, Vec<u8>)>> {
    let meshes = meshes();
    let specs = scenes();
    let mut files = Vec::new();
    for m in meshes.iter().filter(|m| m.written) {
        let bytes = if m.scale == 1.0 {
            encode_stl_binary(&m.builder)?
        } else {
            let mut file = m.builder.clone();
            for p in &mut file.positions {
                *p /= m.scale;
            }
            encode_stl_binary(&file)?
        };
        files.push((m.path.to_owned(), bytes));
    }
    let mut names = std::collections::BTreeSet::new();
    for s in &specs {
        if !names.insert(s.name) {
            bail!("two scenes named {}", s.name);
        }
        files.push((
            format!("scenes/suite/{}.toml", s.name),
            scene_toml(s, &meshes)?.into_bytes(),
        ));
    }
    files.push((
        "scenes/suite/suite.toml".to_owned(),
        manifest(&specs)?.into_bytes(),
    ));
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn root() -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
    }

    /// The committed suite is what the generator writes today: it cannot drift.
    #[test]
    fn committed_suite_equals_a_fresh_generation() {
        let files = generate().expect("generates");
        for (path, bytes) in &files {
            let on_disk = std::fs::read(root().join(path))
                .unwrap_or_else(|e| panic!("{path}: {e} (run cargo xtask suite gen)"));
            assert!(
                on_disk == *bytes,
                "{path} differs: run cargo xtask suite gen"
            );
        }
        // No stale scene in the folder.
        let mut listed: Vec<String> = std::fs::read_dir(root().join("scenes/suite"))
            .expect("scenes/suite")
            .map(|e| {
                format!(
                    "scenes/suite/{}",
                    e.expect("entry").file_name().to_string_lossy()
                )
            })
            .collect();
        listed.sort();
        let mut generated: Vec<String> = files
            .iter()
            .map(|(p, _)| p.clone())
            .filter(|p| p.starts_with("scenes/suite/"))
            .collect();
        generated.sort();
        assert_eq!(listed, generated);
    }

    #[test]
    fn docs_table_is_up_to_date() {
        let doc = std::fs::read_to_string(root().join("docs/suite.md")).expect("docs/suite.md");
        assert!(
            doc_with_table(&doc).expect("markers") == doc,
            "docs/suite.md: run cargo xtask suite gen"
        );
    }

    #[test]
    fn generation_is_deterministic() {
        assert_eq!(generate().expect("once"), generate().expect("twice"));
    }

    /// What issue 17 asks of the suite's size and coverage.
    #[test]
    fn the_suite_covers_what_issue_17_asks() {
        let specs = scenes();
        assert!(specs.len() >= 40, "{}", specs.len());
        let objects: std::collections::BTreeSet<&str> = specs.iter().map(|s| s.object).collect();
        assert!(objects.len() >= 10, "{objects:?}");
        let infeasible = specs
            .iter()
            .filter(|s| matches!(s.expect, Expect::Infeasible { .. }))
            .count();
        assert!(infeasible >= 6, "{infeasible}");
        for tag in [
            "handover",
            "regrasp",
            "shelf",
            "gap",
            "dent",
            "on-side",
            "upside-down",
            "clutter",
            "thousands-of-triangles",
        ] {
            assert!(
                specs.iter().any(|s| s.tags.contains(&tag)),
                "no scene tagged {tag}"
            );
        }
        let meshes = meshes();
        for s in &specs {
            assert!(meshes.iter().any(|m| m.key == s.object), "{}", s.name);
        }
    }

    /// NX-HIRO's hands at the home state (`pickplace robot fk`, collision boxes of
    /// `RARM_JOINT5_Link` and the fingers, mirrored for the left arm), 5 mm wider: world AABBs
    /// that no object or environment part may enter at the start, or the start state is in
    /// collision.
    fn home_hands() -> Vec<([Real; 3], [Real; 3])> {
        let mut boxes = Vec::new();
        for s in [-1.0, 1.0] {
            let m = 0.005;
            let y = |a: Real, b: Real| (s * a).min(s * b);
            let yy = |a: Real, b: Real| (s * a).max(s * b);
            boxes.push((
                [0.29 - m, y(0.127, 0.237) - m, 0.849 - m],
                [0.42 + m, yy(0.127, 0.237) + m, 1.03],
            ));
            boxes.push((
                [0.316 - m, y(0.132, 0.142) - m, 0.789 - m],
                [0.336 + m, yy(0.132, 0.142) + m, 0.85],
            ));
            boxes.push((
                [0.316 - m, y(0.222, 0.232) - m, 0.789 - m],
                [0.336 + m, yy(0.222, 0.232) + m, 0.85],
            ));
        }
        boxes
    }

    fn aabb(points: impl Iterator<Item = Point3>) -> ([Real; 3], [Real; 3]) {
        let mut lo = [Real::INFINITY; 3];
        let mut hi = [Real::NEG_INFINITY; 3];
        for p in points {
            for i in 0..3 {
                lo[i] = lo[i].min(p[i]);
                hi[i] = hi[i].max(p[i]);
            }
        }
        (lo, hi)
    }

    fn overlap(a: &([Real; 3], [Real; 3]), b: &([Real; 3], [Real; 3])) -> bool {
        (0..3).all(|i| a.0[i] < b.1[i] && b.0[i] < a.1[i])
    }

    /// Every scene but the one whose start state is meant to collide starts with the hands
    /// clear of the object and of the environment (the start state is free of collisions).
    #[test]
    fn nothing_starts_in_the_home_hands() {
        let meshes = meshes();
        let mut offenders = Vec::new();
        for s in scenes().iter().filter(|s| s.start_state.is_empty()) {
            let m = &meshes
                .iter()
                .find(|m| m.key == s.object)
                .expect("mesh")
                .builder;
            let (p, q) = start_pose(s, m);
            let t = Vector3::new(p[0], p[1], p[2]);
            let mut boxes = vec![("object", aabb(m.positions.iter().map(|v| q * v + t)))];
            for part in s.parts.iter().filter(|p| p.mesh != "table") {
                let pm = &meshes
                    .iter()
                    .find(|m| m.key == part.mesh)
                    .expect("mesh")
                    .builder;
                let q = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), part.yaw);
                let t = Vector3::from(part.at);
                boxes.push((part.name, aabb(pm.positions.iter().map(|v| q * v + t))));
            }
            for (what, b) in &boxes {
                if home_hands().iter().any(|h| overlap(h, b)) {
                    offenders.push(format!("{}: {what}", s.name));
                }
            }
        }
        assert!(offenders.is_empty(), "{offenders:#?}");
    }

    /// A resting object's lowest point is on its support; a floating one is `lift` above it.
    #[test]
    fn start_poses_rest_on_their_support() {
        let meshes = meshes();
        for s in scenes() {
            let m = &meshes
                .iter()
                .find(|m| m.key == s.object)
                .expect("mesh")
                .builder;
            let (p, q) = start_pose(&s, m);
            let lowest = m
                .positions
                .iter()
                .map(|v| (q * v).z + p[2])
                .fold(Real::INFINITY, Real::min);
            assert!(
                (lowest - s.start[2] - s.lift).abs() < 1e-9,
                "{}: lowest point {lowest}",
                s.name
            );
        }
    }
}
