//! `pickplace clusters`: the JSON of DESIGN.md, the text summary and the PLY picture.

use crate::args;
use crate::support::{Scratch, mesh, ok, run_in, stdout};
use pickplace_geometry::cluster::CLUSTERS_JSON_FORMAT;
use serde_json::Value;

type V3 = [f64; 3];

fn v3(v: &Value) -> V3 {
    let a = v.as_array().expect("an array of 3 numbers");
    assert_eq!(a.len(), 3);
    [0, 1, 2].map(|i| a[i].as_f64().expect("a number"))
}

fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The triangles of a binary STL file, in file order.
fn read_binary_stl(bytes: &[u8]) -> Vec<[V3; 3]> {
    let n = u32::from_le_bytes(bytes[80..84].try_into().expect("4 bytes")) as usize;
    assert_eq!(bytes.len(), 84 + 50 * n, "binary STL");
    let f = |at: usize| {
        f64::from(f32::from_le_bytes(
            bytes[at..at + 4].try_into().expect("4 bytes"),
        ))
    };
    (0..n)
        .map(|t| {
            let base = 84 + 50 * t + 12;
            [0, 1, 2].map(|k| [0, 1, 2].map(|c| f(base + 12 * k + 4 * c)))
        })
        .collect()
}

fn unit_normal(t: &[V3; 3]) -> V3 {
    let n = cross(sub(t[1], t[0]), sub(t[2], t[0]));
    let l = dot(n, n).sqrt();
    n.map(|x| x / l)
}

/// Checks a clusters document against the mesh's own triangles (file order): the clusters
/// partition the triangles, every triangle lies within h ≤ h_max under its cluster's contact
/// plane and faces its normal, and the boundaries lie on the contact planes.
fn check_document(doc: &Value, triangles: &[[V3; 3]], mode: &str, h_max: f64) {
    assert_eq!(doc["format"], CLUSTERS_JSON_FORMAT);
    assert_eq!(doc["mode"], mode);
    assert_eq!(doc["h_max"].as_f64(), Some(h_max));
    assert_eq!(doc["triangle_count"].as_u64(), Some(triangles.len() as u64));
    assert!(
        doc["mesh"]
            .as_str()
            .expect("mesh path")
            .ends_with("can.stl")
    );
    let clusters = doc["clusters"].as_array().expect("clusters");
    let mut owner = vec![None; triangles.len()];
    for (i, c) in clusters.iter().enumerate() {
        assert_eq!(c["id"].as_u64(), Some(i as u64));
        let n = v3(&c["normal"]);
        assert!((dot(n, n) - 1.0).abs() < 1e-9);
        let point = v3(&c["point"]);
        let h = c["h"].as_f64().expect("h");
        assert!((0.0..=h_max).contains(&h), "h {h}");
        let tris: Vec<usize> = c["triangles"]
            .as_array()
            .expect("triangles")
            .iter()
            .map(|t| t.as_u64().expect("index") as usize)
            .collect();
        assert!(
            tris.windows(2).all(|w| w[0] < w[1]),
            "increasing file indices"
        );
        let mut area = 0.0;
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for &t in &tris {
            assert_eq!(owner[t], None, "triangle {t} in two clusters");
            owner[t] = Some(i);
            let tri = &triangles[t];
            // File order: the triangle the index names faces the cluster's way.
            assert!(
                dot(unit_normal(tri), n) > 80f64.to_radians().cos(),
                "triangle {t} vs cluster {i}"
            );
            let s = cross(sub(tri[1], tri[0]), sub(tri[2], tri[0]));
            area += 0.5 * dot(s, s).sqrt();
            for p in tri {
                let d = dot(sub(*p, point), n);
                lo = lo.min(d);
                hi = hi.max(d);
            }
        }
        // STL stores f32: allow its rounding.
        assert!(
            hi < 1e-6 && hi - lo <= h_max + 1e-6,
            "cluster {i}: {lo}..{hi}"
        );
        assert!((area - c["area"].as_f64().expect("area")).abs() < 1e-6 * area.max(1e-3));
        let outer = c["outer_boundary"].as_array().expect("outer_boundary");
        assert!(outer.len() >= 3);
        for p in outer.iter().chain(
            c["holes"]
                .as_array()
                .expect("holes")
                .iter()
                .flat_map(|h| h.as_array().expect("loop")),
        ) {
            assert!(
                dot(sub(v3(p), point), n).abs() < 1e-9,
                "boundary point off the contact plane"
            );
        }
    }
    assert!(
        owner.iter().all(Option::is_some),
        "every triangle clustered"
    );
}

#[test]
fn can_env_json_follows_the_design() {
    let dir = Scratch::new("can-env-json");
    let can = mesh("can.stl");
    let out = ok(&run_in(dir.path(), args!["clusters", can, "--json"]));
    let doc: Value = serde_json::from_str(&out).expect("valid JSON on stdout");
    let triangles = read_binary_stl(&std::fs::read(&can).expect("can.stl"));
    check_document(&doc, &triangles, "env", 0.001);
    assert!(doc.get("pairs").is_none(), "no pairs in env mode");
    let clusters = doc["clusters"].as_array().expect("clusters");
    // Two whole caps; the side in strips of at most h_max = 1 mm sagitta.
    let caps: Vec<&Value> = clusters
        .iter()
        .filter(|c| v3(&c["normal"])[2].abs() > 0.99)
        .collect();
    assert_eq!(caps.len(), 2);
    for cap in caps {
        assert_eq!(cap["triangles"].as_array().map(Vec::len), Some(64));
        assert_eq!(cap["holes"].as_array().map(Vec::len), Some(0));
    }
    assert!(clusters.len() > 10, "{} clusters", clusters.len());
}

#[test]
fn can_finger_json_has_the_papers_four_pairs() {
    let dir = Scratch::new("can-finger-json");
    let can = mesh("can.stl");
    let out = ok(&run_in(
        dir.path(),
        args!["clusters", can, "--mode", "finger", "--json"],
    ));
    let doc: Value = serde_json::from_str(&out).expect("valid JSON on stdout");
    let triangles = read_binary_stl(&std::fs::read(&can).expect("can.stl"));
    check_document(&doc, &triangles, "finger", 0.005);
    let clusters = doc["clusters"].as_array().expect("clusters");
    let pairs = doc["pairs"].as_array().expect("pairs");
    assert_eq!(pairs.len(), 4);
    let mut widths: Vec<f64> = pairs
        .iter()
        .map(|p| p["width"].as_f64().expect("width"))
        .collect();
    widths.sort_by(f64::total_cmp);
    assert!((widths[3] - 0.12).abs() < 1e-6, "cap pair {widths:?}");
    for w in &widths[..3] {
        assert!((w - 0.066).abs() < 0.001, "side pair {widths:?}");
    }
    for p in pairs {
        let ids = p["clusters"].as_array().expect("two ids");
        let [a, b] = [0, 1].map(|k| &clusters[ids[k].as_u64().expect("id") as usize]);
        assert!(
            dot(v3(&a["normal"]), v3(&b["normal"])) <= -0.95,
            "opposite normals"
        );
        assert!(p["overlap_area"].as_f64().expect("overlap") > 0.0);
    }
}

#[test]
fn json_triangle_indices_are_the_files_numbering() {
    // A unit box as OBJ with two degenerate faces (dropped on load) first and in the middle:
    // the JSON must skip their numbers, not renumber the others.
    let dir = Scratch::new("file-order");
    let mut obj =
        String::from("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n");
    let quads = [
        [1, 4, 3, 2],
        [5, 6, 7, 8],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 4, 8, 7],
        [4, 1, 5, 8],
    ];
    obj.push_str("f 1 1 2\n");
    for (i, q) in quads.iter().enumerate() {
        if i == 3 {
            obj.push_str("f 1 2 1\n");
        }
        obj.push_str(&format!("f {} {} {} {}\n", q[0], q[1], q[2], q[3]));
    }
    let path = dir.file("box.obj", obj.as_bytes());
    let out = ok(&run_in(
        dir.path(),
        args!["clusters", path, "--mode", "finger", "--json"],
    ));
    let doc: Value = serde_json::from_str(&out).expect("valid JSON");
    assert_eq!(doc["triangle_count"].as_u64(), Some(14));
    let mut all: Vec<u64> = doc["clusters"]
        .as_array()
        .expect("clusters")
        .iter()
        .flat_map(|c| {
            c["triangles"]
                .as_array()
                .expect("triangles")
                .iter()
                .map(|t| t.as_u64().expect("index"))
        })
        .collect();
    all.sort_unstable();
    let expected: Vec<u64> = (1..14).filter(|&t| t != 7).collect();
    assert_eq!(all, expected);
    // Quad k (fan-triangulated into two triangles) is one face of the box: one cluster.
    for c in doc["clusters"].as_array().expect("clusters") {
        let t: Vec<u64> = c["triangles"]
            .as_array()
            .expect("triangles")
            .iter()
            .map(|t| t.as_u64().expect("i"))
            .collect();
        assert_eq!(t.len(), 2, "{t:?}");
        assert_eq!(t[1], t[0] + 1, "{t:?}");
    }
    assert_eq!(doc["pairs"].as_array().map(Vec::len), Some(3));
}

#[test]
fn ply_picture_colours_every_face_by_cluster() {
    let dir = Scratch::new("ply");
    let ply = dir.join("can-clusters.ply");
    let o = run_in(dir.path(), args!["clusters", mesh("can.stl"), "--ply", ply]);
    let summary = ok(&o);
    assert!(
        summary.starts_with(&format!("{}: 256 triangles, ", mesh("can.stl").display())),
        "{summary}"
    );
    let clusters: usize = summary
        .split(" triangles, ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .expect("cluster count in the summary");
    let text = std::fs::read_to_string(&ply).expect("PLY written");
    let (header, body) = text.split_once("end_header\n").expect("PLY header");
    assert!(header.starts_with("ply\nformat ascii 1.0\n"));
    assert!(header.contains("element face 256\n"));
    assert!(header.contains("property uchar red\n"));
    let vertices: usize = header
        .lines()
        .find_map(|l| l.strip_prefix("element vertex "))
        .and_then(|n| n.parse().ok())
        .expect("vertex count");
    let lines: Vec<&str> = body.lines().collect();
    assert_eq!(lines.len(), vertices + 256);
    let mut colours = std::collections::BTreeSet::new();
    for face in &lines[vertices..] {
        let f: Vec<u32> = face
            .split(' ')
            .map(|x| x.parse().expect("integer"))
            .collect();
        assert_eq!(f.len(), 7);
        assert_eq!(f[0], 3);
        assert!(f[1..4].iter().all(|&v| (v as usize) < vertices));
        colours.insert([f[4], f[5], f[6]]);
    }
    assert_eq!(colours.len(), clusters, "one colour per cluster");
    assert_eq!(
        dir.files(""),
        ["can-clusters.ply"],
        "no temporary file left behind"
    );
}

#[test]
fn output_is_deterministic() {
    let dir = Scratch::new("deterministic");
    let run = || {
        stdout(&run_in(
            dir.path(),
            args!["clusters", mesh("mug.stl"), "--mode", "finger", "--json"],
        ))
    };
    let first = run();
    assert!(!first.is_empty());
    assert_eq!(first, run());
}
