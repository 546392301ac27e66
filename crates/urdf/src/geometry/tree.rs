//! Forward kinematics of a whole URDF tree: every link's pose, not only a serial chain's.
//!
//! Self-collision sampling needs the links off the arm's chain too (the FR3's two fingers
//! hang from the hand side by side). Each link's frame in its root link's frame is
//! `T_child = T_parent · origin_j · M_j(q_j)` for its parent joint `j` (the convention of
//! [`crate::chain`]: `M` a rotation about, or translation along, the joint axis; identity
//! for fixed joints). The tree's **variables** are its revolute, continuous and prismatic
//! joints that do not mimic another, file order; a mimic joint takes
//! `multiplier · q[master] + offset` (a mimic joint whose master is not a variable is a
//! variable itself). Floating and planar joints are held at their origin.

use nalgebra::Isometry3;

use crate::chain::{origin_isometry, value_of, ChainJoint, Drive, JointKind, JointLimits};
use crate::error::UrdfError;
use crate::model::UrdfModel;

/// A joint variable of the tree.
#[derive(Clone, Debug)]
pub struct TreeVariable {
    /// The URDF joint name.
    pub joint: String,
    /// Revolute, continuous or prismatic.
    pub kind: JointKind,
    /// Its limits (continuous: ±∞).
    pub limits: JointLimits,
}

/// The parent joint of a link, resolved.
#[derive(Clone, Debug)]
struct Parent {
    link: usize,
    /// `None` for fixed (and floating, planar) joints.
    moving: Option<ChainJoint>,
    origin: Isometry3<f64>,
}

/// Every link of a URDF with its parent joint, for whole-tree forward kinematics.
#[derive(Clone, Debug)]
pub struct LinkTree {
    names: Vec<String>,
    parents: Vec<Option<Parent>>,
    /// Link indices, every parent before its children.
    order: Vec<usize>,
    variables: Vec<TreeVariable>,
}

impl LinkTree {
    /// Indexes the joints of `model`; errors are those of a bad axis or limit.
    pub fn new(model: &UrdfModel) -> Result<LinkTree, UrdfError> {
        let robot = model.robot();
        let names: Vec<String> = robot.links.iter().map(|l| l.name.clone()).collect();
        let index = |n: &str| names.iter().position(|m| m == n).expect("checked on load");
        let mut parents: Vec<Option<Parent>> = vec![None; names.len()];
        let mut variables = Vec::new();
        let mut var_of = std::collections::HashMap::new();
        // Two passes: variables first, so a mimic joint finds its master's index.
        for j in &robot.joints {
            if j.mimic.is_none() && moving_kind(&j.joint_type).is_some() {
                var_of.insert(j.name.clone(), variables.len());
                let kind = moving_kind(&j.joint_type).expect("moving");
                variables.push(TreeVariable {
                    joint: j.name.clone(),
                    kind,
                    limits: model.limits_of(j, kind)?,
                });
            }
        }
        for j in &robot.joints {
            let origin = origin_isometry(&j.origin);
            let moving = match moving_kind(&j.joint_type) {
                None => None,
                Some(kind) => {
                    let master = j.mimic.as_ref().and_then(|m| var_of.get(&m.joint).copied());
                    let drive = match (master, &j.mimic) {
                        (Some(master), Some(m)) => Drive::Mimic {
                            master,
                            multiplier: m.multiplier.unwrap_or(1.0),
                            offset: m.offset.unwrap_or(0.0),
                        },
                        _ => {
                            let i = *var_of.entry(j.name.clone()).or_insert_with(|| {
                                variables.push(TreeVariable {
                                    joint: j.name.clone(),
                                    kind,
                                    limits: JointLimits {
                                        lower: f64::NEG_INFINITY,
                                        upper: f64::INFINITY,
                                        velocity: f64::INFINITY,
                                        effort: f64::INFINITY,
                                    },
                                });
                                variables.len() - 1
                            });
                            Drive::Actuated(i)
                        }
                    };
                    Some(ChainJoint {
                        name: j.name.clone(),
                        kind,
                        origin,
                        axis: model.axis_of(j)?,
                        limits: model.limits_of(j, kind)?,
                        drive,
                        child_link: j.child.link.clone(),
                    })
                }
            };
            parents[index(&j.child.link)] = Some(Parent {
                link: index(&j.parent.link),
                moving,
                origin,
            });
        }
        let order = topological(&parents);
        Ok(LinkTree {
            names,
            parents,
            order,
            variables,
        })
    }

    /// Link names, URDF file order (the order of [`LinkTree::poses`]).
    pub fn link_names(&self) -> &[String] {
        &self.names
    }

    /// The joint variables, in the order `q` lists them.
    pub fn variables(&self) -> &[TreeVariable] {
        &self.variables
    }

    /// Every link's pose in its root link's frame (file order) for the variables `q`
    /// (`q.len() == variables().len()`, panics otherwise).
    pub fn poses(&self, q: &[f64]) -> Vec<Isometry3<f64>> {
        assert_eq!(q.len(), self.variables.len(), "one value per tree variable");
        let mut out = vec![Isometry3::identity(); self.names.len()];
        for &i in &self.order {
            if let Some(p) = &self.parents[i] {
                let motion = match &p.moving {
                    Some(j) => j.motion(value_of(j.drive, q)),
                    None => Isometry3::identity(),
                };
                out[i] = out[p.link] * p.origin * motion;
            }
        }
        out
    }

    /// The link index of the parent of link `i` and whether the joint between moves.
    pub(crate) fn parent_of(&self, i: usize) -> Option<(usize, bool)> {
        self.parents[i]
            .as_ref()
            .map(|p| (p.link, p.moving.is_some()))
    }
}

fn moving_kind(t: &urdf_rs::JointType) -> Option<JointKind> {
    match t {
        urdf_rs::JointType::Revolute => Some(JointKind::Revolute),
        urdf_rs::JointType::Continuous => Some(JointKind::Continuous),
        urdf_rs::JointType::Prismatic => Some(JointKind::Prismatic),
        _ => None,
    }
}

/// Link indices with every parent before its children (links on a parent loop, which the
/// chain extraction reports, are left out).
fn topological(parents: &[Option<Parent>]) -> Vec<usize> {
    let n = parents.len();
    let mut children = vec![Vec::new(); n];
    let mut order = Vec::with_capacity(n);
    for (i, p) in parents.iter().enumerate() {
        match p {
            Some(p) => children[p.link].push(i),
            None => order.push(i),
        }
    }
    let mut k = 0;
    while k < order.len() {
        let i = order[k];
        order.extend(children[i].iter().copied());
        k += 1;
    }
    order
}
