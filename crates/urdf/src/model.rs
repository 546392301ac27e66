//! A parsed URDF with its kinematic tree indexed: which joint is each link's parent, which
//! links are roots and leaves, which joints mimic others.
//!
//! Loading checks what every later step relies on: link and joint names are unique, every
//! joint's parent and child links exist, no link has two parent joints, every `<mimic>`
//! names an existing joint. Geometry (visuals, collisions, inertials) is kept untouched in
//! [`UrdfModel::robot`] and not interpreted here.

use std::collections::HashMap;
use std::path::Path;

use crate::error::UrdfError;
use crate::limits::MAX_LINKS;

/// A `<mimic>` relation: `q[joint] = multiplier · q[master] + offset` (URDF defaults:
/// multiplier 1, offset 0).
#[derive(Clone, Debug, PartialEq)]
pub struct Mimic {
    /// The mimic joint (the one carrying the `<mimic>` element).
    pub joint: String,
    /// The joint it follows.
    pub master: String,
    /// Factor on the master's value.
    pub multiplier: f64,
    /// Added after scaling (rad or m).
    pub offset: f64,
}

/// A URDF document with its tree indexed by link and joint name.
#[derive(Clone, Debug)]
pub struct UrdfModel {
    source: String,
    robot: urdf_rs::Robot,
    links: HashMap<String, usize>,
    joints: HashMap<String, usize>,
    /// Per link (index into `robot.links`): the index of the joint whose child it is.
    parent_joint: Vec<Option<usize>>,
}

impl UrdfModel {
    /// Reads and indexes the URDF file at `path`; errors name the path as given. Only a
    /// regular file of at most [`pregrasp_limits::MAX_DESCRIPTION_BYTES`] is read.
    pub fn from_file(path: impl AsRef<Path>) -> Result<Self, UrdfError> {
        let path = path.as_ref();
        let file = path.display().to_string();
        let text = pregrasp_limits::read_text_limited(path, pregrasp_limits::MAX_DESCRIPTION_BYTES)
            .map_err(|source| UrdfError::Io {
                file: file.clone(),
                source,
            })?;
        Self::from_urdf_str(&text, &file)
    }

    /// Parses and indexes URDF text; `source` names it in error messages (a path, or any
    /// label such as `"<inline>"`). Text nested deeper or with more elements than
    /// [`pregrasp_limits::xml::Shape::DESCRIPTION`] allows is refused before the (recursive)
    /// URDF reader sees it.
    pub fn from_urdf_str(text: &str, source: &str) -> Result<Self, UrdfError> {
        pregrasp_limits::xml::check(text, pregrasp_limits::xml::Shape::DESCRIPTION).map_err(
            |e| UrdfError::Parse {
                file: source.to_string(),
                message: e.to_string(),
            },
        )?;
        let robot = urdf_rs::read_from_string(text).map_err(|e| UrdfError::Parse {
            file: source.to_string(),
            message: e.to_string(),
        })?;
        Self::from_robot(robot, source)
    }

    /// Indexes an already parsed `urdf_rs::Robot`.
    pub fn from_robot(robot: urdf_rs::Robot, source: &str) -> Result<Self, UrdfError> {
        let file = || source.to_string();
        for (count, what) in [(robot.links.len(), "links"), (robot.joints.len(), "joints")] {
            if count > MAX_LINKS {
                return Err(UrdfError::TooLarge {
                    file: file(),
                    what: format!("{count} {what}"),
                    max: MAX_LINKS.to_string(),
                });
            }
        }
        let mut links = HashMap::new();
        for (i, l) in robot.links.iter().enumerate() {
            if links.insert(l.name.clone(), i).is_some() {
                return Err(UrdfError::DuplicateName {
                    file: file(),
                    element: "link",
                    name: l.name.clone(),
                });
            }
        }
        let mut joints = HashMap::new();
        let mut parent_joint = vec![None; robot.links.len()];
        for (i, j) in robot.joints.iter().enumerate() {
            if joints.insert(j.name.clone(), i).is_some() {
                return Err(UrdfError::DuplicateName {
                    file: file(),
                    element: "joint",
                    name: j.name.clone(),
                });
            }
            let unknown = |link: &str, role: &str| UrdfError::UnknownLink {
                file: file(),
                link: link.to_string(),
                context: format!("{role} of joint `{}`", j.name),
            };
            if !links.contains_key(&j.parent.link) {
                return Err(unknown(&j.parent.link, "parent"));
            }
            let Some(&child) = links.get(&j.child.link) else {
                return Err(unknown(&j.child.link, "child"));
            };
            if let Some(other) = parent_joint[child] {
                let other: &urdf_rs::Joint = &robot.joints[other];
                return Err(UrdfError::NotSerial {
                    file: file(),
                    link: j.child.link.clone(),
                    problem: format!(
                        "is the child of two joints, `{}` and `{}` (a closed loop)",
                        other.name, j.name
                    ),
                });
            }
            parent_joint[child] = Some(i);
        }
        for j in &robot.joints {
            if let Some(m) = &j.mimic {
                if !joints.contains_key(&m.joint) {
                    return Err(UrdfError::UnknownMimicMaster {
                        file: file(),
                        joint: j.name.clone(),
                        master: m.joint.clone(),
                    });
                }
            }
        }
        Ok(UrdfModel {
            source: source.to_string(),
            robot,
            links,
            joints,
            parent_joint,
        })
    }

    /// The source named in error messages (the path as given, or the label passed).
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The `<robot name>`.
    pub fn name(&self) -> &str {
        &self.robot.name
    }

    /// The parsed document (links with their visual and collision geometry, joints,
    /// materials).
    pub fn robot(&self) -> &urdf_rs::Robot {
        &self.robot
    }

    /// Every link name, in file order.
    pub fn link_names(&self) -> impl Iterator<Item = &str> {
        self.robot.links.iter().map(|l| l.name.as_str())
    }

    /// True when the file declares a link of that name.
    pub fn has_link(&self, name: &str) -> bool {
        self.links.contains_key(name)
    }

    /// Links that are no joint's child (a well-formed URDF has exactly one), file order.
    pub fn root_links(&self) -> Vec<&str> {
        self.robot
            .links
            .iter()
            .zip(&self.parent_joint)
            .filter(|(_, p)| p.is_none())
            .map(|(l, _)| l.name.as_str())
            .collect()
    }

    /// Links that are no joint's parent (tool frames, fingertips), file order.
    pub fn leaf_links(&self) -> Vec<&str> {
        let mut has_child = vec![false; self.robot.links.len()];
        for j in &self.robot.joints {
            has_child[self.links[&j.parent.link]] = true;
        }
        self.robot
            .links
            .iter()
            .zip(has_child)
            .filter(|(_, c)| !c)
            .map(|(l, _)| l.name.as_str())
            .collect()
    }

    /// Every `<mimic>` relation of the file, file order.
    pub fn mimic_joints(&self) -> Vec<Mimic> {
        self.robot
            .joints
            .iter()
            .filter_map(|j| {
                j.mimic.as_ref().map(|m| Mimic {
                    joint: j.name.clone(),
                    master: m.joint.clone(),
                    multiplier: m.multiplier.unwrap_or(1.0),
                    offset: m.offset.unwrap_or(0.0),
                })
            })
            .collect()
    }

    /// The joint of that name.
    pub fn joint(&self, name: &str) -> Option<&urdf_rs::Joint> {
        self.joints.get(name).map(|&i| &self.robot.joints[i])
    }

    /// The joint whose child is `link` (`None` for a root or an unknown link).
    pub fn parent_joint(&self, link: &str) -> Option<&urdf_rs::Joint> {
        let i = *self.links.get(link)?;
        self.parent_joint[i].map(|j| &self.robot.joints[j])
    }
}
