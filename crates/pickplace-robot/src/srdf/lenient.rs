//! An SRDF read as leniently as MoveIt reads it: what names a link, joint or group the model
//! lacks, and what is malformed, is left out with one warning per element, and the rest is
//! used. A planner needs little of an SRDF (its arm groups, the disabled collision pairs);
//! refusing a whole file over a group state that names a robot's toes would throw away the
//! hundreds of collision pairs that make its roadmaps fast.

use super::{GroupSpec, Srdf, SrdfWarning};
use crate::model::RobotModel;
use std::collections::{BTreeMap, BTreeSet};

/// What [`leave_out_unknowns`] keeps and drops.
pub(super) struct Kept {
    /// The SRDF without the elements left out.
    pub srdf: Srdf,
    /// Groups left out whole, with why (a malformed member).
    pub groups_left_out: BTreeMap<String, String>,
    /// Groups kept with members left out, with what was left out and why.
    pub members_left_out: BTreeMap<String, String>,
    /// One warning per element left out or changed, in file order of kind.
    pub warnings: Vec<SrdfWarning>,
}

/// The SRDF with every element that names something `model` lacks left out (an element
/// inside one, such as a group's joint or a state's value, or the element itself when it
/// cannot stand without the name), each reported once. `is_virtual` tells the joints that
/// are not URDF joints but the SRDF's virtual ones (kept: the resolver reports them).
pub(super) fn leave_out_unknowns(
    model: &RobotModel,
    srdf: &Srdf,
    is_virtual: &dyn Fn(&str) -> bool,
) -> Kept {
    let mut out = srdf.clone();
    out.skipped.clear();
    let mut warnings = Vec::new();
    let mut left_out = |element: String, reason: String| {
        warnings.push(SrdfWarning::LeftOut { element, reason });
    };
    let link_known = |name: &str| model.link_index(name).is_some();
    let joint_known = |name: &str| model.joint_index(name).is_some() || is_virtual(name);

    // Malformed elements were skipped by the parser; a group with a malformed member is left
    // out whole (its meaning is unknown), and it is named where it is used.
    let mut groups_left_out: BTreeMap<String, String> = BTreeMap::new();
    for k in &srdf.skipped {
        match &k.group {
            Some(group) => {
                let why = format!("its member {} is malformed ({})", k.element, k.reason);
                left_out(format!("group {group:?}"), format!("{why}: group left out"));
                groups_left_out.entry(group.clone()).or_insert(why);
            }
            None => left_out(k.element.clone(), format!("{}: skipped", k.reason)),
        }
    }
    out.groups
        .retain(|g| !groups_left_out.contains_key(&g.name));

    out.virtual_joints.retain(|v| {
        let keep = link_known(&v.child_link);
        if !keep {
            left_out(
                format!("virtual_joint {:?}", v.name),
                format!(
                    "its child link {:?} is not in the URDF: left out",
                    v.child_link
                ),
            );
        }
        keep
    });

    let defined: BTreeSet<String> = out.groups.iter().map(|g| g.name.clone()).collect();
    let group_known = |name: &str| defined.contains(name);
    let why_unknown_group = |name: &str| match groups_left_out.get(name) {
        Some(_) => format!("group {name:?} is left out (above)"),
        None => format!("group {name:?} is not defined in the SRDF"),
    };
    let mut members_left_out: BTreeMap<String, String> = BTreeMap::new();
    for group in &mut out.groups {
        let mut problems: Vec<String> = Vec::new();
        group.chains.retain(|c| {
            let problem = match [&c.base_link, &c.tip_link]
                .into_iter()
                .find(|l| !link_known(l))
            {
                Some(l) => Some(format!("link {l:?} is not in the URDF")),
                None => {
                    let (base, tip) = (
                        model.link_index(&c.base_link),
                        model.link_index(&c.tip_link),
                    );
                    match (base, tip) {
                        (Some(b), Some(t)) if !model.is_ancestor(b, t) => Some(format!(
                            "tip {:?} is not below base {:?}",
                            c.tip_link, c.base_link
                        )),
                        _ => None,
                    }
                }
            };
            if let Some(p) = &problem {
                problems.push(format!(
                    "chain {:?} -> {:?} left out: {p}",
                    c.base_link, c.tip_link
                ));
            }
            problem.is_none()
        });
        group.joints.retain(|j| {
            let keep = joint_known(j);
            if !keep {
                problems.push(format!("joint {j:?} left out: not in the URDF"));
            }
            keep
        });
        group.links.retain(|l| {
            let keep = link_known(l);
            if !keep {
                problems.push(format!("link {l:?} left out: not in the URDF"));
            }
            keep
        });
        group.subgroups.retain(|sub| {
            let keep = group_known(sub);
            if !keep {
                problems.push(format!("subgroup left out: {}", why_unknown_group(sub)));
            }
            keep
        });
        if !problems.is_empty() {
            let why = problems.join("; ");
            left_out(format!("group {:?}", group.name), why.clone());
            members_left_out.insert(group.name.clone(), why);
        }
    }
    for (owner, sub) in break_cycles(&mut out.groups) {
        let why = format!("subgroup {sub:?} left out: it includes {owner:?} again");
        left_out(format!("group {owner:?}"), why.clone());
        members_left_out
            .entry(owner)
            .and_modify(|w| *w = format!("{w}; {why}"))
            .or_insert(why);
    }

    out.end_effectors.retain(|e| {
        let problem = if !link_known(&e.parent_link) {
            Some(format!(
                "its parent_link {:?} is not a link of the URDF",
                e.parent_link
            ))
        } else {
            std::iter::once(&e.group)
                .chain(e.parent_group.iter())
                .find(|g| !group_known(g))
                .map(|g| why_unknown_group(g))
        };
        if let Some(p) = &problem {
            left_out(
                format!("end_effector {:?}", e.name),
                format!("{p}: left out"),
            );
        }
        problem.is_none()
    });

    out.group_states.retain_mut(|state| {
        let element = format!("group_state {:?}", state.name);
        if !group_known(&state.group) {
            left_out(
                element,
                format!("{}: left out", why_unknown_group(&state.group)),
            );
            return false;
        }
        let mut problems: Vec<String> = Vec::new();
        state.values.retain(|(j, _)| {
            let keep = joint_known(j);
            if !keep {
                problems.push(format!("{j:?}"));
            }
            keep
        });
        let unknown = problems.len();
        state.multi_dof_values.retain(|(j, values)| {
            let keep = model.joint_index(j).is_none();
            if !keep {
                problems.push(format!(
                    "{j:?} ({} numbers for a one-variable joint)",
                    values.len()
                ));
            }
            keep
        });
        if !problems.is_empty() {
            let what = if unknown == problems.len() {
                "joints not in the URDF"
            } else {
                "values it cannot take"
            };
            left_out(
                element,
                format!("values left out ({what}): {}", problems.join(", ")),
            );
        }
        true
    });

    out.passive_joints.retain(|j| {
        let keep = joint_known(j);
        if !keep {
            left_out(
                format!("passive_joint {j:?}"),
                "not in the URDF: left out".to_owned(),
            );
        }
        keep
    });

    // Disabled pairs naming a link the URDF lacks (a variant's links, a renamed part): one
    // warning per unknown link, every other pair kept.
    let mut unknown_links: BTreeMap<String, usize> = BTreeMap::new();
    out.disabled_collisions.retain(|d| {
        let missing = [&d.link1, &d.link2].into_iter().find(|l| !link_known(l));
        if let Some(l) = missing {
            *unknown_links.entry(l.clone()).or_default() += 1;
        }
        missing.is_none()
    });
    let kept = out.disabled_collisions.len();
    for (link, pairs) in unknown_links {
        left_out(
            "disable_collisions".to_owned(),
            format!(
                "{pairs} pair(s) name link {link:?}, which the URDF lacks: left out ({kept} pairs kept)"
            ),
        );
    }
    Kept {
        srdf: out,
        groups_left_out,
        members_left_out,
        warnings,
    }
}

/// Removes subgroup references that close a cycle (a group that includes itself through its
/// subgroups), returning each as (group, subgroup). Deterministic: groups in file order,
/// subgroups in their order.
fn break_cycles(groups: &mut [GroupSpec]) -> Vec<(String, String)> {
    let mut removed = Vec::new();
    loop {
        let index: BTreeMap<&str, usize> = groups
            .iter()
            .enumerate()
            .map(|(i, g)| (g.name.as_str(), i))
            .collect();
        // Depth-first from each group; the first edge into a group on the current path closes
        // a cycle. A group explored whole without one is not explored again.
        fn closing_edge(
            groups: &[GroupSpec],
            index: &BTreeMap<&str, usize>,
            at: usize,
            path: &mut Vec<usize>,
            done: &mut [bool],
        ) -> Option<(usize, usize)> {
            if done[at] {
                return None;
            }
            path.push(at);
            for (k, sub) in groups[at].subgroups.iter().enumerate() {
                let Some(&next) = index.get(sub.as_str()) else {
                    continue;
                };
                if path.contains(&next) {
                    return Some((at, k));
                }
                if let Some(edge) = closing_edge(groups, index, next, path, done) {
                    return Some(edge);
                }
            }
            path.pop();
            done[at] = true;
            None
        }
        let mut done = vec![false; groups.len()];
        let edge = (0..groups.len())
            .find_map(|i| closing_edge(groups, &index, i, &mut Vec::new(), &mut done));
        let Some((owner, k)) = edge else {
            return removed;
        };
        let sub = groups[owner].subgroups.remove(k);
        removed.push((groups[owner].name.clone(), sub));
    }
}
