//! [`Gripper::derive`]: the gripper measured on the URDF by forward kinematics (drives,
//! fingers, the opening table, pads, tool point, the grasp planner's simple model).

use super::*;

impl Gripper {
    /// Derives the gripper at the end of an arm whose model variables are `arm_variables`.
    ///
    /// # Errors
    /// A [`GripperError`] saying what the hand lacks: no drive, not two fingers, an opening
    /// that does not grow, a continuous or unlimited drive.
    pub fn derive(
        model: &RobotModel,
        arm_variables: &[usize],
        options: &GripperOptions,
    ) -> Result<Self, GripperError> {
        options.check()?;
        let arm_tip = arm_tip(model, arm_variables)?;
        let tip_name = model.links()[arm_tip].name.clone();
        let subtree = subtree(model, arm_tip);
        // Drives: actuated joints of the subtree.
        let mut drive_vars: Vec<usize> = Vec::new();
        for &l in &subtree {
            if let Some(j) = model.links()[l].parent_joint
                && let JointValueSource::Variable(v) = model.joints()[j].source
            {
                drive_vars.push(v);
            }
        }
        if drive_vars.is_empty() {
            return Err(GripperError::NoDrive { tip: tip_name });
        }
        for &v in &drive_vars {
            let joint = model.variable_joint(v);
            if joint.joint_type == JointType::Continuous
                || !joint.limits.lower.is_finite()
                || !joint.limits.upper.is_finite()
            {
                return Err(GripperError::BadDrive {
                    joint: joint.name.clone(),
                    reason: "a finger joint needs finite limits (it is continuous or unlimited)",
                });
            }
            if joint.limits.upper - joint.limits.lower <= 1e-9 {
                return Err(GripperError::BadDrive {
                    joint: joint.name.clone(),
                    reason: "its limits are equal: the finger cannot move",
                });
            }
        }
        // Fingers: links moved by a drive, grouped by the first moving joint below the hand.
        let moves = |joint: usize| match model.joints()[joint].source {
            JointValueSource::Fixed => false,
            JointValueSource::Variable(v) | JointValueSource::Mimic { variable: v, .. } => {
                drive_vars.contains(&v)
            }
        };
        let mut below = vec![false; model.links().len()];
        below[arm_tip] = true;
        for &l in &subtree {
            below[l] = true;
        }
        let mut groups: Vec<(usize, Vec<usize>)> = Vec::new();
        for &l in &subtree {
            let first_moving = model
                .joint_path(l)
                .into_iter()
                .filter(|&j| below[model.joints()[j].parent_link])
                .find(|&j| moves(j));
            if let Some(j) = first_moving {
                match groups.iter_mut().find(|(k, _)| *k == j) {
                    Some((_, links)) => links.push(l),
                    None => groups.push((j, vec![l])),
                }
            }
        }
        let driver = |joint: usize| match model.joints()[joint].source {
            JointValueSource::Variable(v) | JointValueSource::Mimic { variable: v, .. } => v,
            JointValueSource::Fixed => usize::MAX,
        };
        let mut with_geometry: Vec<(usize, Vec<usize>, Vec<Piece>)> = Vec::new();
        for (j, links) in &groups {
            let pieces: Vec<Piece> = links.iter().flat_map(|&l| pieces_of(model, l)).collect();
            if !pieces.is_empty() {
                with_geometry.push((driver(*j), links.clone(), pieces));
            }
        }
        // One moving jaw closing against the hand: the fixed jaw is the hand's geometry that
        // no drive moves (the links below the arm's tip, else the tip's own geometry).
        let fixed_jaw = drive_vars.len() == 1 && with_geometry.len() == 1;
        if fixed_jaw {
            let moving: Vec<usize> = groups.iter().flat_map(|(_, l)| l.iter().copied()).collect();
            let mut links: Vec<usize> = subtree
                .iter()
                .copied()
                .filter(|l| !moving.contains(l))
                .collect();
            let mut pieces: Vec<Piece> = links.iter().flat_map(|&l| pieces_of(model, l)).collect();
            if pieces.is_empty() {
                links = vec![arm_tip];
                pieces = pieces_of(model, arm_tip);
            }
            if !pieces.is_empty() {
                with_geometry.push((usize::MAX, links, pieces));
            }
        }
        if drive_vars.len() > 2 {
            return Err(GripperError::BadDrive {
                joint: model.variable_joint(drive_vars[2]).name.clone(),
                reason: "a parallel gripper has one or two independent finger joints; this is a third",
            });
        }
        if with_geometry.len() < 2 {
            return Err(GripperError::NotTwoFingers {
                tip: tip_name,
                found: with_geometry.len(),
            });
        }
        let mut sample = Sampler {
            model,
            arm_tip,
            q: model.zero_configuration(),
        };
        // Each drive's open end: the limit at which the fingers are farther apart (measured
        // between the two most distant finger groups, the others held mid-range).
        let mids: Vec<Drive> = drive_vars
            .iter()
            .map(|&v| {
                let l = model.variable_joint(v).limits;
                let mid = 0.5 * (l.lower + l.upper);
                Drive {
                    variable: v,
                    closed: mid,
                    open: mid,
                }
            })
            .collect();
        // Split the moving groups into the two fingers. Two drives: one finger each. One drive:
        // the fingers move towards each other, so a group's side is the sign of its motion
        // over the drive's stroke along the largest motion.
        let side_of: Vec<usize> = if fixed_jaw {
            // The moving jaw first, the fixed one second.
            (0..with_geometry.len())
                .map(|i| usize::from(i > 0))
                .collect()
        } else if drive_vars.len() == 2 {
            with_geometry
                .iter()
                .map(|(v, _, _)| usize::from(*v == drive_vars[1]))
                .collect()
        } else {
            let at = |sample: &mut Sampler<'_>, lower: bool| {
                let ends: Vec<Drive> = mids
                    .iter()
                    .map(|d| {
                        let l = model.variable_joint(d.variable).limits;
                        let x = if lower { l.lower } else { l.upper };
                        Drive {
                            closed: x,
                            open: x,
                            ..*d
                        }
                    })
                    .collect();
                sample.set(&ends, 0.0);
                let poses = sample.hand_poses();
                with_geometry
                    .iter()
                    .map(|(_, _, pieces)| centroid(pieces, &poses))
                    .collect::<Vec<Point3>>()
            };
            let from = at(&mut sample, true);
            let to = at(&mut sample, false);
            let motion: Vec<Vector3> = from.iter().zip(&to).map(|(a, b)| b - a).collect();
            let largest = motion
                .iter()
                .copied()
                .max_by(|a, b| a.norm().total_cmp(&b.norm()))
                .unwrap_or_else(Vector3::zeros);
            motion
                .iter()
                .map(|m| usize::from(m.dot(&largest) < 0.0))
                .collect()
        };
        let mut sides: [(Vec<usize>, Vec<Piece>); 2] = Default::default();
        for (i, (_, links, pieces)) in with_geometry.into_iter().enumerate() {
            sides[side_of[i]].0.extend(links);
            sides[side_of[i]].1.extend(pieces);
        }
        if sides.iter().any(|(_, pieces)| pieces.is_empty()) {
            return Err(GripperError::NotTwoFingers {
                tip: tip_name,
                found: 1,
            });
        }
        // The line between the fingers, at mid stroke.
        sample.set(&mids, 0.0);
        let poses = sample.hand_poses();
        let (ca, cb) = (centroid(&sides[0].1, &poses), centroid(&sides[1].1, &poses));
        let axis = (cb - ca)
            .try_normalize(1e-9)
            .ok_or_else(|| GripperError::NotTwoFingers {
                tip: tip_name.clone(),
                found: 1,
            })?;
        let mid_point = Point3::from((ca.coords + cb.coords) * 0.5);
        let [(links_a, pieces_a), (links_b, pieces_b)] = sides;
        // The pads: on each side, the pieces of geometry that reach farthest towards the finger
        // tips (within 5 mm), the approach being roughly from the hand's origin to the fingers, across the
        // line between them. Proximal links (PR2's, TALOS's) and cross bars (Baxter's) are not pads.
        // A jaw turning against a fixed one: its joint gives both axes (the line between the
        // sides' centres is no finger axis when the fixed side is the whole hand).
        let turning = if fixed_jaw {
            turning_jaw(&mut sample, &mids, &pieces_a, &pieces_b)
        } else {
            None
        };
        let rough_approach = turning
            .map(|t| t.approach)
            .or_else(|| (mid_point.coords - axis * mid_point.coords.dot(&axis)).try_normalize(1e-6))
            .unwrap_or_else(|| {
                axis.cross(&Vector3::x())
                    .try_normalize(1e-6)
                    .unwrap_or(Vector3::z())
            });
        let pads_of = |pieces: Vec<Piece>| -> Vec<Piece> {
            let reach = |piece: &Piece| {
                piece
                    .points
                    .iter()
                    .map(|p| (poses[piece.link] * p).coords.dot(&rough_approach))
                    .fold(Real::NEG_INFINITY, Real::max)
            };
            let far = pieces.iter().map(reach).fold(Real::NEG_INFINITY, Real::max);
            pieces
                .into_iter()
                .filter(|p| reach(p) >= far - 0.005)
                .collect()
        };
        let pieces = [pads_of(pieces_a), pads_of(pieces_b)];
        // The closing axis: from one finger's pads to the other's, at mid stroke (with one
        // moving jaw: the way its pads move where it meets the fixed jaw, at the drive's end
        // where the pads are closest, since a turning jaw is across the fixed jaw's face only
        // there; a sliding jaw: its slide); the opening is the gap between the pads along it
        // (negative when interleaved fingers pass each other, as TALOS's do when fully
        // closed).
        let between = if let Some(t) = turning {
            t.closing
        } else {
            sample.set(&mids, 0.0);
            let poses = sample.hand_poses();
            centroid(&pieces[1], &poses) - centroid(&pieces[0], &poses)
        };
        let closing = between
            .try_normalize(1e-9)
            .ok_or_else(|| GripperError::NotTwoFingers {
                tip: tip_name.clone(),
                found: 1,
            })?;
        let distance = |sample: &Sampler<'_>| -> Result<Real, GripperError> {
            Ok(axis_gap(&pieces, &sample.hand_poses(), &closing))
        };
        let mut drives = Vec::with_capacity(mids.len());
        for (i, d) in mids.iter().enumerate() {
            let l = model.variable_joint(d.variable).limits;
            let mut probe = mids.clone();
            probe[i].closed = l.lower;
            sample.set(&probe, 0.0);
            let at_lower = distance(&sample)?;
            probe[i].closed = l.upper;
            sample.set(&probe, 0.0);
            let at_upper = distance(&sample)?;
            let (closed, open) = if at_upper >= at_lower {
                (l.lower, l.upper)
            } else {
                (l.upper, l.lower)
            };
            drives.push(Drive {
                variable: d.variable,
                closed,
                open,
            });
        }
        // Pads when closed.
        sample.set(&drives, 0.0);
        let poses = sample.hand_poses();
        let pts_a = side_points(&pieces[0], &poses);
        let pts_b = side_points(&pieces[1], &poses);
        let inner_a = pts_a
            .iter()
            .map(|p| p.coords.dot(&closing))
            .fold(Real::NEG_INFINITY, Real::max);
        let inner_b = pts_b
            .iter()
            .map(|p| p.coords.dot(&closing))
            .fold(Real::INFINITY, Real::min);
        let pad_a: Vec<Point3> = pts_a
            .iter()
            .copied()
            .filter(|p| p.coords.dot(&closing) >= inner_a - PAD_TOLERANCE)
            .collect();
        let pad_b: Vec<Point3> = pts_b
            .iter()
            .copied()
            .filter(|p| p.coords.dot(&closing) <= inner_b + PAD_TOLERANCE)
            .collect();
        let pad_centre = Point3::from((mean(&pad_a).coords + mean(&pad_b).coords) * 0.5);
        // Approach: from the hand's origin (the arm tip) to the pads, across the closing axis.
        let raw = pad_centre.coords - closing * pad_centre.coords.dot(&closing);
        let approach = raw.try_normalize(1e-6).ok_or_else(|| GripperError::CannotOpen {
            tip: tip_name.clone(),
            reason: "has its pads on the line of the closing axis through the arm's last joint: no approach direction".to_owned(),
        })?;
        let lateral = closing.cross(&approach);
        let along = |p: &Point3, axis: &Vector3| p.coords.dot(axis);
        let pads: Vec<&Point3> = pad_a.iter().chain(&pad_b).collect();
        let (a_lo, a_hi) = extent(pads.iter().map(|p| along(p, &approach)));
        let (l_lo, l_hi) = extent(pads.iter().map(|p| along(p, &lateral)));
        let face_depth = (a_hi - a_lo).max(1e-4);
        let pad_depth = options.pad_depth.map_or(face_depth, |d| d.min(face_depth));
        let pad_width = options.pad_width.unwrap_or((l_hi - l_lo).max(1e-4));

        // The opening table.
        let tabulate = |sample: &mut Sampler<'_>, drives: &[Drive]| {
            (0..TABLE_SAMPLES)
                .map(|k| {
                    let s = k as Real / (TABLE_SAMPLES - 1) as Real;
                    sample.set(drives, s);
                    Ok((s, distance(sample)?))
                })
                .collect::<Result<Vec<_>, GripperError>>()
        };
        let mut table = tabulate(&mut sample, &drives)?;
        if turning.is_some() {
            // A turning jaw opens widest across the fixed jaw's face before the end of its
            // stroke (it turns back over the hand after): its stroke ends there.
            let widest = table
                .iter()
                .enumerate()
                .max_by(|a, b| a.1.1.total_cmp(&b.1.1).then(b.0.cmp(&a.0)))
                .map_or(TABLE_SAMPLES - 1, |(k, _)| k);
            if widest > 0 && widest < TABLE_SAMPLES - 1 {
                let s = table[widest].0;
                for d in &mut drives {
                    d.open = d.closed + s * (d.open - d.closed);
                }
                table = tabulate(&mut sample, &drives)?;
            }
        }
        let measured_min = table[0].1;
        let measured_max = table[TABLE_SAMPLES - 1].1;
        if measured_max - measured_min < 0.002 {
            return Err(GripperError::CannotOpen {
                tip: tip_name,
                reason: format!(
                    "opens only from {:.1} mm to {:.1} mm between its closed and open joint limits",
                    measured_min * 1e3,
                    measured_max * 1e3
                ),
            });
        }
        if measured_max < MIN_OPENING {
            return Err(GripperError::CannotOpen {
                tip: tip_name,
                reason: format!(
                    "opens to {:.1} mm at most: its fingers' geometry overlaps at every opening (a jaw whose convex hull takes in the other)",
                    measured_max * 1e3
                ),
            });
        }
        // Monotone: a dip of more than 0.5 mm means the fingers cross or the split is wrong.
        let mut running = measured_min;
        for &(s, o) in &table {
            if o < running - 0.0005 {
                return Err(GripperError::CannotOpen {
                    tip: tip_name,
                    reason: format!(
                        "does not open steadily: the opening falls from {:.1} mm to {:.1} mm at {:.0} % of the stroke",
                        running * 1e3,
                        o * 1e3,
                        s * 100.0
                    ),
                });
            }
            running = running.max(o);
        }
        // Make it non-decreasing (small numerical dips).
        let mut best = Real::NEG_INFINITY;
        for entry in &mut table {
            best = Real::max(best, entry.1);
            entry.1 = best;
        }

        // Midway between the pads when closed; with a fixed jaw, on its pad (a grasp's centre
        // is then half the width away: [`Gripper::centre_from_tcp`]).
        let c_mid = if fixed_jaw {
            inner_b
        } else {
            0.5 * (inner_a + inner_b)
        };
        let tcp_origin =
            closing * c_mid + approach * (a_hi - pad_depth / 2.0) + lateral * (0.5 * (l_lo + l_hi));
        let rotation =
            Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[lateral, closing, approach]));
        let tip_from_tcp_raw = Isometry3::from_parts(
            Translation3::from(tcp_origin),
            UnitQuaternion::from_rotation_matrix(&rotation),
        );
        let tip_from_tcp = tip_from_tcp_raw * Translation3::from(options.tool_offset);
        let tcp_from_tip = tip_from_tcp.inverse();
        // Finger sizes along the TCP axes, and the palm's box, in the TCP frame.
        let in_tcp = |p: &Point3| tcp_from_tip * p;
        let finger_a: Vec<Point3> = pts_a.iter().map(in_tcp).collect();
        let (z_lo, z_hi) = extent(finger_a.iter().map(|p| p.z));
        let (y_lo, y_hi) = extent(finger_a.iter().map(|p| p.y));
        let finger_length = (z_hi - z_lo).max(pad_depth);
        let finger_thickness = (y_hi - y_lo).max(1e-4);
        let moving: Vec<usize> = links_a.iter().chain(&links_b).copied().collect();
        let mut palm_links: Vec<usize> = subtree
            .iter()
            .copied()
            .filter(|l| !moving.contains(l))
            .collect();
        if palm_links
            .iter()
            .all(|&l| model.links()[l].collisions.is_empty())
        {
            palm_links.push(arm_tip);
        }
        // A fixed jaw that is the tip's own geometry (one mesh with the hand's body, split by
        // the loader): the palm is the part of it behind the moving jaw's root, the rest is
        // the jaw.
        let palm_points: Vec<Point3> = palm_links
            .iter()
            .flat_map(|&l| pieces_of(model, l))
            .flat_map(|piece| {
                let pose = poses[piece.link];
                let jaw = links_b.contains(&piece.link);
                piece.points.into_iter().map(move |p| (jaw, pose * p))
            })
            .map(|(jaw, p)| (jaw, in_tcp(&p)))
            .filter(|(jaw, p)| !jaw || p.z < z_lo)
            .map(|(_, p)| p)
            .collect();
        let palm = if palm_points.is_empty() {
            // No palm geometry: a thin plate behind the finger roots.
            let back = z_lo;
            (
                Point3::new(-pad_width / 2.0, -measured_max / 2.0, back - 0.005),
                Point3::new(pad_width / 2.0, measured_max / 2.0, back),
            )
        } else {
            let (x0, x1) = extent(palm_points.iter().map(|p| p.x));
            let (y0, y1) = extent(palm_points.iter().map(|p| p.y));
            let (z0, z1) = extent(palm_points.iter().map(|p| p.z));
            (Point3::new(x0, y0, z0), Point3::new(x1, y1, z1))
        };
        let opening_max = options
            .opening_max
            .map_or(measured_max, |m| m.min(measured_max));
        let mut hand_links = subtree.clone();
        hand_links.insert(0, arm_tip);
        Ok(Self {
            arm_tip,
            hand_links,
            finger_links: [links_a, links_b],
            drives,
            pieces,
            table,
            opening_min: measured_min.max(0.0),
            opening_max,
            squeeze: options.squeeze,
            tip_from_tcp,
            pad_width,
            pad_depth,
            finger_length,
            finger_thickness,
            palm,
            fixed_jaw,
        })
    }

    /// Whether one jaw is fixed to the hand and the other closes against it (a jaw turning
    /// or sliding against a fixed one, as on many small arms). The tool point then lies on
    /// the fixed jaw's pad.
    pub fn has_fixed_jaw(&self) -> bool {
        self.fixed_jaw
    }

    /// The tool point seen from the centre of a grasp `width` wide (the point midway between
    /// the two contact patches, where the grasp planner puts it): the identity when both
    /// jaws move; with a fixed jaw, `width / 2 +` [`FIXED_JAW_CLEARANCE`] along the closing
    /// axis `y`, so that the fixed jaw's pad stands that clearance off the object's side.
    pub fn centre_from_tcp(&self, width: Real) -> Isometry3 {
        if self.fixed_jaw {
            Isometry3::translation(0.0, width / 2.0 + FIXED_JAW_CLEARANCE, 0.0)
        } else {
            Isometry3::identity()
        }
    }
}

impl GripperOptions {
    /// Refuses values out of range: a squeeze outside [0, 0.02] m, a pad size or largest
    /// opening outside (0, 1] m, a tool offset beyond 1 m (the rules [`Gripper::derive`]
    /// applies first; an overrides file is checked with them when it is read).
    ///
    /// # Errors
    /// [`GripperError::BadOption`] naming the first bad option.
    pub fn check(&self) -> Result<(), GripperError> {
        check_options(self)
    }
}

fn check_options(o: &GripperOptions) -> Result<(), GripperError> {
    let bad = |name, reason| Err(GripperError::BadOption { name, reason });
    if !o.squeeze.is_finite() || o.squeeze < 0.0 || o.squeeze > 0.02 {
        return bad("squeeze", "must be between 0 and 0.02 m");
    }
    for (name, v) in [
        ("pad_depth", o.pad_depth),
        ("pad_width", o.pad_width),
        ("opening_max", o.opening_max),
    ] {
        if let Some(v) = v
            && (!v.is_finite() || v <= 0.0 || v > 1.0)
        {
            return bad(name, "must be positive and at most 1 m");
        }
    }
    if !o
        .tool_offset
        .iter()
        .all(|x| x.is_finite() && x.abs() <= 1.0)
    {
        return bad("tool_offset", "must be finite and within 1 m");
    }
    Ok(())
}

/// The child link of the arm's deepest joint, checking that the joints are one chain.
fn arm_tip(model: &RobotModel, variables: &[usize]) -> Result<usize, GripperError> {
    let mut links: Vec<usize> = variables
        .iter()
        .filter_map(|&v| {
            model
                .variable_joints()
                .get(v)
                .map(|&j| model.joints()[j].child_link)
        })
        .collect();
    if links.is_empty() {
        return Err(GripperError::NoArmJoints);
    }
    // Deepest first: the one whose root path is longest.
    links.sort_by_key(|&l| std::cmp::Reverse(model.joint_path(l).len()));
    let tip = links[0];
    for &l in &links[1..] {
        if !model.is_ancestor(l, tip) {
            let name = |l: usize| {
                model.links()[l]
                    .parent_joint
                    .map_or_else(String::new, |j| model.joints()[j].name.clone())
            };
            return Err(GripperError::NotAChain {
                first: name(tip),
                second: name(l),
            });
        }
    }
    Ok(tip)
}

/// Every link strictly below `link`.
fn subtree(model: &RobotModel, link: usize) -> Vec<usize> {
    (0..model.links().len())
        .filter(|&l| l != link && model.is_ancestor(link, l))
        .collect()
}

/// The convex pieces of a link's collision geometry, with sample points.
fn pieces_of(model: &RobotModel, link: usize) -> Vec<Piece> {
    let mut out = Vec::new();
    for g in &model.links()[link].collisions {
        let local = shape_points(&g.shape);
        let points: Vec<Point3> = local.iter().map(|p| g.link_from_shape * p).collect();
        let hull_points: Vec<_> = points.iter().map(parry::point).collect();
        if let Some(shape) = SharedShape::convex_hull(&hull_points) {
            out.push(Piece {
                link,
                shape,
                points,
            });
        }
    }
    out
}

/// Points on a shape's surface, in its own frame: exact for boxes and meshes (their corners
/// and vertices), 24 around each rim for round shapes.
fn shape_points(shape: &Shape) -> Vec<Point3> {
    let ring = |r: Real, z: Real| -> Vec<Point3> {
        (0..24)
            .map(|k| {
                let a = k as Real * std::f64::consts::TAU / 24.0;
                Point3::new(r * a.cos(), r * a.sin(), z)
            })
            .collect()
    };
    match shape {
        Shape::Box { half_extents: h } => {
            let mut v = Vec::with_capacity(8);
            for sx in [-1.0, 1.0] {
                for sy in [-1.0, 1.0] {
                    for sz in [-1.0, 1.0] {
                        v.push(Point3::new(sx * h.x, sy * h.y, sz * h.z));
                    }
                }
            }
            v
        }
        Shape::Cylinder { radius, length } => {
            let mut v = ring(*radius, -length / 2.0);
            v.extend(ring(*radius, length / 2.0));
            v
        }
        Shape::Capsule { radius, length } => {
            let mut v = Vec::new();
            for k in 0..=4 {
                let phi = k as Real * std::f64::consts::FRAC_PI_2 / 4.0;
                let (r, dz) = (radius * phi.cos(), radius * phi.sin());
                v.extend(ring(r, length / 2.0 + dz));
                v.extend(ring(r, -length / 2.0 - dz));
            }
            v
        }
        Shape::Sphere { radius } => {
            let mut v = Vec::new();
            for k in -4..=4 {
                let phi = k as Real * std::f64::consts::FRAC_PI_2 / 4.0;
                v.extend(ring(radius * phi.cos(), radius * phi.sin()));
            }
            v
        }
        Shape::Mesh { mesh, .. } => mesh.vertices().to_vec(),
    }
}

/// Forward kinematics of the hand for the closing parameter.
struct Sampler<'a> {
    model: &'a RobotModel,
    arm_tip: usize,
    q: Vec<Real>,
}

impl Sampler<'_> {
    fn set(&mut self, drives: &[Drive], s: Real) {
        for d in drives {
            self.q[d.variable] = d.closed + s * (d.open - d.closed);
        }
    }

    /// Every link's pose in the arm tip's frame (identity for links not computed).
    fn hand_poses(&self) -> Vec<Isometry3> {
        match self.model.link_poses(&self.q) {
            Ok(poses) => {
                let tip_from_root = poses[self.arm_tip].inverse();
                poses.iter().map(|p| tip_from_root * p).collect()
            }
            Err(_) => vec![Isometry3::identity(); self.model.links().len()],
        }
    }
}

fn centroid(pieces: &[Piece], poses: &[Isometry3]) -> Point3 {
    let pts: Vec<Point3> = side_points(pieces, poses);
    mean(&pts)
}

fn side_points(pieces: &[Piece], poses: &[Isometry3]) -> Vec<Point3> {
    pieces
        .iter()
        .flat_map(|piece| piece.points.iter().map(move |p| poses[piece.link] * p))
        .collect()
}

fn mean(points: &[Point3]) -> Point3 {
    if points.is_empty() {
        return Point3::origin();
    }
    let sum: Vector3 = points.iter().map(|p| p.coords).sum();
    Point3::from(sum / points.len() as Real)
}

fn extent(values: impl Iterator<Item = Real>) -> (Real, Real) {
    values.fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    })
}

/// The gap between the two sides' pads along the closing axis (side a → side b).
fn axis_gap(pieces: &[Vec<Piece>; 2], poses: &[Isometry3], closing: &Vector3) -> Real {
    let along = |side: &[Piece]| {
        side_points(side, poses)
            .into_iter()
            .map(|p| p.coords.dot(closing))
    };
    let inner_a = along(&pieces[0]).fold(Real::NEG_INFINITY, Real::max);
    let inner_b = along(&pieces[1]).fold(Real::INFINITY, Real::min);
    inner_b - inner_a
}

/// The axes of a jaw that turns against a fixed one: `approach` from its joint towards its tip
/// and `closing` the way its tip moves, both where it meets the fixed jaw (the drive's end
/// where its tip is nearest the fixed side), in the arm tip's frame. `None` for a drive that
/// does not turn.
#[derive(Debug, Clone, Copy)]
struct TurningJaw {
    approach: Vector3,
    closing: Vector3,
}

fn turning_jaw(
    sample: &mut Sampler<'_>,
    mids: &[Drive],
    moving: &[Piece],
    fixed: &[Piece],
) -> Option<TurningJaw> {
    let [drive] = mids else {
        return None;
    };
    let model = sample.model;
    let joint = model.variable_joint(drive.variable);
    if joint.joint_type != JointType::Revolute {
        return None;
    }
    let child = joint.child_link;
    // The jaw's tip: its point farthest from the joint's axis, in the jaw's own frame.
    sample.set(
        &[Drive {
            closed: drive.closed,
            open: drive.closed,
            ..*drive
        }],
        0.0,
    );
    let poses = sample.hand_poses();
    let jaw_from_tip = poses[child].inverse();
    let tip_point = moving
        .iter()
        .flat_map(|piece| {
            piece
                .points
                .iter()
                .map(|p| jaw_from_tip * (poses[piece.link] * p))
        })
        .max_by(|a, b| {
            let off_axis = |p: &Point3| {
                (p.coords - joint.axis.into_inner() * p.coords.dot(&joint.axis)).norm()
            };
            off_axis(a).total_cmp(&off_axis(b))
        })?;
    // Where that tip is, with the joint at `x`, and how near it is to the fixed side.
    let mut at = |x: Real| {
        sample.set(
            &[Drive {
                closed: x,
                open: x,
                ..*drive
            }],
            0.0,
        );
        let poses = sample.hand_poses();
        let tip = poses[child] * tip_point;
        let gap = side_points(fixed, &poses)
            .iter()
            .map(|p| (p - tip).norm())
            .fold(Real::INFINITY, Real::min);
        (poses[child], tip, gap)
    };
    let limits = joint.limits;
    let (closed, open) = if at(limits.upper).2 < at(limits.lower).2 {
        (limits.upper, limits.lower)
    } else {
        (limits.lower, limits.upper)
    };
    let (pose, tip, _) = at(closed);
    let (_, near, _) = at(closed + 0.01 * (open - closed));
    let axis = pose.rotation * joint.axis.into_inner();
    let arm = tip.coords - pose.translation.vector;
    let approach = (arm - axis * arm.dot(&axis)).try_normalize(1e-9)?;
    let mut closing = axis.cross(&approach);
    if closing.dot(&(tip - near)) < 0.0 {
        closing = -closing;
    }
    Some(TurningJaw { approach, closing })
}
