use pickplace_geometry::math::Point3;
use pickplace_geometry::mesh::{MeshOptions, TriMesh};

#[test]
fn tetrahedron_is_closed() {
    let p = [
        Point3::new(0.0, 0.0, 0.0),
        Point3::new(1.0, 0.0, 0.0),
        Point3::new(0.0, 1.0, 0.0),
        Point3::new(0.0, 0.0, 1.0),
    ];
    let t = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
    let mesh = TriMesh::from_soup(&p, &t, &MeshOptions::default()).expect("valid");
    assert!(mesh.report().is_closed());
    for i in 0..4 {
        assert_eq!(mesh.adjacency().neighbours(i).len(), 3);
    }
}
