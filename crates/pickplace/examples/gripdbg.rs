use pickplace::robot::gripper::GripObject;
use pickplace::{Arm, Plan, Setup, SetupOptions};
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let setup = Setup::load(
        a[1].as_ref(),
        &SetupOptions {
            cache_dir: Some("target/pickplace-cache".into()),
            ..Default::default()
        },
    )
    .unwrap();
    let plan = Plan::from_json(&std::fs::read_to_string(&a[2]).unwrap()).unwrap();
    let obj = GripObject::new(&setup.object_mesh).unwrap();
    let e = plan
        .events
        .iter()
        .find(|e| e.kind == pickplace::plan::EventKind::Grasp)
        .unwrap();
    let p = plan
        .trajectory
        .iter()
        .find(|p| p.time_from_start >= e.time - 1e-9)
        .unwrap();
    let arm = if e.link.starts_with("right") {
        Arm::Right
    } else {
        Arm::Left
    };
    let g = &setup.arm(arm).gripper;
    let poses: Vec<_> = setup
        .model
        .link_poses(&p.positions)
        .unwrap()
        .into_iter()
        .map(|x| setup.world_from_root * x)
        .collect();
    let tcp = setup.world_from_root * setup.arm(arm).ik.chain().pose(&p.positions);
    let l = e.link_from_object.to_isometry().unwrap();
    let o = tcp * l;
    println!("gaps {:?}", g.finger_gaps(&poses, &obj, &o).unwrap());
    for &v in &setup.arm(arm).finger_variables {
        println!(
            "finger {} = {}",
            setup.model.variable_joint(v).name,
            p.positions[v]
        );
    }
    println!(
        "object start {:?}\nobject held {:?}",
        setup.object_start.translation.vector, o.translation.vector
    );
    for (s, links) in g.finger_links().iter().enumerate() {
        for &lk in links {
            println!(
                "side {s} {} at {:?}",
                setup.model.links()[lk].name,
                (tcp.inverse() * poses[lk]).translation.vector
            );
        }
    }
}
