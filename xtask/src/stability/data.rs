//! Test data of `cargo xtask stability`: the pinned pybullet wheel (its `pybullet_data/`
//! objects), the Python venv of the independent measurement, and the object list.

use anyhow::{Context, bail};
use pickplace_geometry::math::Real;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The wheel: pybullet 3.2.7 for CPython 3.11 on manylinux x86-64, from PyPI.
pub const WHEEL_NAME: &str =
    "pybullet-3.2.7-cp311-cp311-manylinux_2_17_x86_64.manylinux2014_x86_64.whl";
/// Its sha256 (as PyPI lists it).
pub const WHEEL_SHA256: &str = "5d858abf7c12a21ef3ed351cf81dac1b5e486ec25c9ab59bfc84beb89034edff";
/// What the venv gets besides the wheel (exact versions; numpy, scipy and networkx are what
/// `trimesh.poses.compute_stable_poses` needs).
pub const PIP_PINS: [&str; 4] = [
    "trimesh==4.12.2",
    "numpy==2.4.6",
    "scipy==1.17.1",
    "networkx==3.6.1",
];

/// One object of the test set, before loading.
#[derive(Debug, Clone)]
pub struct ObjectSpec {
    /// `pybullet/duck`, `random/007`, `generated/can-02-mm`.
    pub name: String,
    /// Mesh file.
    pub path: PathBuf,
    /// Per-axis scale to metres (the URDF's `<mesh scale>`; 0.001 for files in millimetres).
    pub scale: [Real; 3],
}

fn sha256(path: &Path) -> anyhow::Result<String> {
    let out = Command::new("sha256sum")
        .arg(path)
        .output()
        .context("running sha256sum")?;
    if !out.status.success() {
        bail!("sha256sum {} failed", path.display());
    }
    Ok(String::from_utf8_lossy(&out.stdout)
        .split_whitespace()
        .next()
        .unwrap_or_default()
        .to_owned())
}

/// The wheel in `dir` (target/objects), checked against [`WHEEL_SHA256`]
/// ([`fetch_pinned_wheel`]; for CPython 3.11 on manylinux x86-64, whatever the running
/// Python).
///
/// # Errors
/// pip fails, or the file's hash differs.
pub fn fetch_wheel(dir: &Path) -> anyhow::Result<PathBuf> {
    fetch_pinned_wheel(
        "xtask stability",
        dir,
        WHEEL_NAME,
        WHEEL_SHA256,
        "pybullet==3.2.7",
        &[
            "--python-version",
            "3.11",
            "--implementation",
            "cp",
            "--abi",
            "cp311",
            "--platform",
            "manylinux_2_17_x86_64",
            "--platform",
            "manylinux2014_x86_64",
        ],
    )
}

/// The wheel `name` in `dir`, checked against `sha256` (as PyPI lists it):
/// [`fetch_pinned_file`] with `--only-binary :all:` and the `platform` arguments.
///
/// # Errors
/// pip fails, or the file's hash differs.
pub fn fetch_pinned_wheel(
    task: &str,
    dir: &Path,
    name: &str,
    sha256_hex: &str,
    requirement: &str,
    platform: &[&str],
) -> anyhow::Result<PathBuf> {
    let mut pip_args = vec!["--only-binary", ":all:"];
    pip_args.extend_from_slice(platform);
    fetch_pinned_file(task, dir, name, sha256_hex, requirement, &pip_args)
}

/// The file `name` (a wheel or a source archive) in `dir`, checked against `sha256` (as PyPI
/// lists it): kept when present with the right hash, else copied from `$PICKPLACE_WHEELS/`
/// when a file there has the right hash, else fetched with `pip download --no-deps
/// REQUIREMENT` and `pip_args`. `task` names the command in messages.
///
/// # Errors
/// pip fails, or the file's hash differs.
pub fn fetch_pinned_file(
    task: &str,
    dir: &Path,
    name: &str,
    sha256_hex: &str,
    requirement: &str,
    pip_args: &[&str],
) -> anyhow::Result<PathBuf> {
    std::fs::create_dir_all(dir)?;
    let wheel = dir.join(name);
    if wheel.is_file() && sha256(&wheel)? == sha256_hex {
        return Ok(wheel);
    }
    if let Some(wheels) = std::env::var_os("PICKPLACE_WHEELS") {
        let candidate = Path::new(&wheels).join(name);
        if candidate.is_file() && sha256(&candidate)? == sha256_hex {
            eprintln!("{task}: using {}", candidate.display());
            std::fs::copy(&candidate, &wheel)?;
            return Ok(wheel);
        }
    }
    eprintln!("{task}: pip download --no-deps {requirement}");
    let status = Command::new("python3")
        .args(["-m", "pip", "download", "--no-deps", requirement])
        .args(pip_args)
        .arg("-d")
        .arg(dir)
        .status()
        .context("running python3 -m pip download")?;
    if !status.success() {
        bail!("pip download {requirement} failed ({status})");
    }
    let got = sha256(&wheel)?;
    if got != sha256_hex {
        bail!("{}: sha256 {got}, expected {sha256_hex}", wheel.display());
    }
    Ok(wheel)
}

/// Unzips `pybullet_data/` of the wheel into `dir` once (a stamp file marks completion).
///
/// # Errors
/// `unzip` fails.
pub fn unpack(wheel: &Path, dir: &Path) -> anyhow::Result<PathBuf> {
    let data = dir.join("pybullet_data");
    let stamp = dir.join("pybullet_data.unpacked");
    if stamp.is_file() && data.is_dir() {
        return Ok(data);
    }
    let status = Command::new("unzip")
        .args(["-q", "-o"])
        .arg(wheel)
        .arg("pybullet_data/*")
        .arg("-d")
        .arg(dir)
        .status()
        .context("running unzip")?;
    if !status.success() {
        bail!("unzip {} failed ({status})", wheel.display());
    }
    std::fs::write(&stamp, WHEEL_SHA256)?;
    Ok(data)
}

/// The venv `dir/venv` with the wheel and [`PIP_PINS`], created when missing or when its
/// stamp differs; returns its Python.
///
/// # Errors
/// venv or pip fails.
pub fn venv(wheel: &Path, dir: &Path) -> anyhow::Result<PathBuf> {
    let venv = dir.join("venv");
    let python = venv.join("bin/python");
    let stamp_path = venv.join("stability-requirements.txt");
    let stamp = format!("{WHEEL_NAME} {WHEEL_SHA256}\n{}\n", PIP_PINS.join("\n"));
    if python.is_file() && std::fs::read_to_string(&stamp_path).ok().as_deref() == Some(&stamp) {
        return Ok(python);
    }
    eprintln!("xtask stability: creating {}", venv.display());
    let status = Command::new("python3")
        .args(["-m", "venv", "--clear"])
        .arg(&venv)
        .status()
        .context("running python3 -m venv")?;
    if !status.success() {
        bail!("python3 -m venv {} failed ({status})", venv.display());
    }
    let status = Command::new(&python)
        .args(["-m", "pip", "install", "--quiet"])
        .arg(wheel)
        .args(PIP_PINS)
        .status()
        .context("running pip install")?;
    if !status.success() {
        bail!("pip install into {} failed ({status})", venv.display());
    }
    std::fs::write(&stamp_path, stamp)?;
    Ok(python)
}

/// The value of `attribute="…"` in `tag` (the text of one XML element).
fn attribute<'a>(tag: &'a str, attribute: &str) -> Option<&'a str> {
    let key = format!("{attribute}=\"");
    let start = tag.find(&key)? + key.len();
    let end = tag[start..].find('"')? + start;
    Some(&tag[start..end])
}

/// The first `<mesh …>` element inside `<section>…</section>` of `urdf`: file name and scale.
fn mesh_in(urdf: &str, section: &str) -> Option<(String, [Real; 3])> {
    let open = urdf.find(&format!("<{section}"))?;
    let close = urdf[open..].find(&format!("</{section}>"))? + open;
    let body = &urdf[open..close];
    let m = body.find("<mesh")?;
    let tag = &body[m..m + body[m..].find('>')?];
    let file = attribute(tag, "filename")?.to_owned();
    let scale = match attribute(tag, "scale") {
        Some(s) => {
            let v: Vec<Real> = s
                .split_whitespace()
                .filter_map(|x| x.parse().ok())
                .collect();
            match v.as_slice() {
                [a, b, c] => [*a, *b, *c],
                [a] => [*a; 3],
                _ => return None,
            }
        }
        None => [1.0; 3],
    };
    Some((file, scale))
}

/// The mesh of a URDF object: the collision mesh with its scale, or the visual mesh when the
/// collision is a primitive (pybullet's cube, jenga, domino and lego collide as boxes) or a
/// V-HACD decomposition of it (the duck: the visual `duck.obj` is the surface, the decomposition
/// a set of overlapping hulls).
pub fn urdf_mesh(urdf_path: &Path) -> anyhow::Result<(PathBuf, [Real; 3])> {
    let text = std::fs::read_to_string(urdf_path)
        .with_context(|| format!("reading {}", urdf_path.display()))?;
    let collision = mesh_in(&text, "collision");
    let visual = mesh_in(&text, "visual");
    let chosen = match (collision, visual) {
        (Some(c), Some(v)) if c.0.to_lowercase().contains("vhacd") && c.0 != v.0 => v,
        (Some(c), _) => c,
        (None, Some(v)) => v,
        (None, None) => bail!("{}: no <mesh> element", urdf_path.display()),
    };
    let dir = urdf_path.parent().unwrap_or(Path::new("."));
    Ok((dir.join(&chosen.0), chosen.1))
}

/// The pybullet objects: the first `random` of `random_urdfs/` and the small everyday objects
/// (not `toys/concave_box`: a 2 m box, outside the scale the drop test is tuned for).
pub fn pybullet_objects(data: &Path, random: usize) -> anyhow::Result<Vec<ObjectSpec>> {
    let mut out = Vec::new();
    for (name, urdf) in [
        ("duck", "duck_vhacd.urdf"),
        ("cube-small", "cube_small.urdf"),
        ("teddy", "teddy_vhacd.urdf"),
        ("lego", "lego/lego.urdf"),
        ("jenga", "jenga/jenga.urdf"),
        ("domino", "domino/domino.urdf"),
        ("mug", "objects/mug.urdf"),
    ] {
        let (path, scale) = urdf_mesh(&data.join(urdf))?;
        out.push(ObjectSpec {
            name: format!("pybullet/{name}"),
            path,
            scale,
        });
    }
    // The toys without a URDF of their own are in metres.
    for toy in ["cube", "cylinder", "prism"] {
        out.push(ObjectSpec {
            name: format!("pybullet/toy-{toy}"),
            path: data.join(format!("toys/{toy}.obj")),
            scale: [1.0; 3],
        });
    }
    for i in 0..random {
        let urdf = data.join(format!("random_urdfs/{i:03}/{i:03}.urdf"));
        let (path, scale) = urdf_mesh(&urdf)?;
        out.push(ObjectSpec {
            name: format!("random/{i:03}"),
            path,
            scale,
        });
    }
    Ok(out)
}
