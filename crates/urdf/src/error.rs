//! Errors of loading a URDF and extracting a serial chain from it.
//!
//! Every variant names the source (`file`: the path as given, or the name passed with a
//! string) and the element at fault (link or joint name), so a message alone says where to
//! look.

/// Why a URDF could not be loaded or a chain could not be extracted.
#[derive(Debug, thiserror::Error)]
pub enum UrdfError {
    /// The file could not be read.
    #[error("{file}: cannot read the file: {source}")]
    Io {
        /// The file.
        file: String,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The text is not a URDF `urdf-rs` can read (bad XML, a missing required attribute, a
    /// number that does not parse, ...).
    #[error("{file}: not a valid URDF: {message}")]
    Parse {
        /// The source.
        file: String,
        /// The parser's message.
        message: String,
    },
    /// Two `<link>` or two `<joint>` elements share a name.
    #[error("{file}: {element} name `{name}` is used twice")]
    DuplicateName {
        /// The source.
        file: String,
        /// `"link"` or `"joint"`.
        element: &'static str,
        /// The repeated name.
        name: String,
    },
    /// A link name that the file does not declare.
    #[error("{file}: unknown link `{link}` ({context})")]
    UnknownLink {
        /// The source.
        file: String,
        /// The missing link.
        link: String,
        /// Who asked for it: "base link", "tool link", or "parent of joint `j`".
        context: String,
    },
    /// A `<mimic>` names a joint that the file does not declare.
    #[error("{file}: joint `{joint}` mimics unknown joint `{master}`")]
    UnknownMimicMaster {
        /// The source.
        file: String,
        /// The mimic joint.
        joint: String,
        /// The joint it names.
        master: String,
    },
    /// A mimic joint on the chain follows a joint that is not on the chain (or is itself a
    /// mimic joint), so its value would not be a function of the chain's joints.
    #[error(
        "{file}: joint `{joint}` on the chain from `{base}` to `{tip}` mimics `{master}`, which \
         is not an actuated joint of that chain"
    )]
    MimicOutsideChain {
        /// The source.
        file: String,
        /// The mimic joint.
        joint: String,
        /// The joint it mimics.
        master: String,
        /// Base link of the chain.
        base: String,
        /// Tool link of the chain.
        tip: String,
    },
    /// The tool link does not lie below the base link in the kinematic tree.
    #[error(
        "{file}: no path from link `{base}` down to link `{tip}` (the tool link must be a \
         descendant of the base link; `{tip}` descends from root `{tip_root}`)"
    )]
    NoPath {
        /// The source.
        file: String,
        /// The base link asked for.
        base: String,
        /// The tool link asked for.
        tip: String,
        /// The root reached walking up from `tip`.
        tip_root: String,
    },
    /// The joints do not form a tree: a link has two parent joints, or the parent relation
    /// loops.
    #[error("{file}: not a serial chain: link `{link}` {problem}")]
    NotSerial {
        /// The source.
        file: String,
        /// The link at fault.
        link: String,
        /// What is wrong with it.
        problem: String,
    },
    /// A joint type a serial chain cannot hold (floating, planar, spherical) lies on the path.
    #[error(
        "{file}: joint `{joint}` is of type {kind}, which a serial chain cannot hold (fixed, \
         revolute, continuous and prismatic joints only)"
    )]
    UnsupportedJoint {
        /// The source.
        file: String,
        /// The joint.
        joint: String,
        /// Its URDF type.
        kind: String,
    },
    /// A revolute or prismatic joint without position limits. URDF requires `<limit>` on
    /// them; `urdf-rs` reads an absent one as all zeros, so a limit with
    /// `lower = upper = velocity = 0` (which could not move anyway) is reported as missing.
    #[error(
        "{file}: joint `{joint}` ({kind}) has no <limit lower=.. upper=.. velocity=..> element \
         (required for revolute and prismatic joints)"
    )]
    MissingLimit {
        /// The source.
        file: String,
        /// The joint.
        joint: String,
        /// `"revolute"` or `"prismatic"`.
        kind: &'static str,
    },
    /// A `<limit>` with `lower > upper`, a NaN, or a negative velocity.
    #[error("{file}: joint `{joint}` has an invalid <limit>: {problem}")]
    BadLimit {
        /// The source.
        file: String,
        /// The joint.
        joint: String,
        /// What is wrong.
        problem: String,
    },
    /// A `<collision>` element whose geometry no robot can have: a size, radius or scale that
    /// is negative, not finite or beyond [`crate::geometry::MAX_LINK_EXTENT`], or a mesh with
    /// an empty filename.
    #[error("{file}: link `{link}`: <collision> {problem}")]
    BadCollision {
        /// The source.
        file: String,
        /// The link.
        link: String,
        /// What is wrong, naming the element and value.
        problem: String,
    },
    /// A moving joint whose `<axis xyz>` is zero or not finite.
    #[error("{file}: joint `{joint}` has an unusable <axis xyz=\"{axis}\"> (zero or not finite)")]
    BadAxis {
        /// The source.
        file: String,
        /// The joint.
        joint: String,
        /// The axis as written.
        axis: String,
    },
    /// An `<origin>` with a value that is not finite.
    #[error("{file}: joint `{joint}` has a non-finite <origin>")]
    BadOrigin {
        /// The source.
        file: String,
        /// The joint.
        joint: String,
    },
    /// The path between the two links has no moving joint.
    #[error("{file}: no moving joint between link `{base}` and link `{tip}`")]
    NoJoints {
        /// The source.
        file: String,
        /// The base link.
        base: String,
        /// The tool link.
        tip: String,
    },
    /// A `<collision>` mesh file found in none of the places its name can resolve to.
    #[error(
        "{file}: link `{link}`: collision mesh `{filename}` not found (searched: {})",
        searched_text(searched)
    )]
    MissingMesh {
        /// The URDF.
        file: String,
        /// The link whose `<collision>` names it.
        link: String,
        /// The filename as written in the URDF.
        filename: String,
        /// The directories looked in, in order.
        searched: Vec<String>,
    },
    /// A collision mesh file that could not be read or parsed, or has no usable vertices.
    #[error("{file}: link `{link}`: collision mesh {path}: {message}")]
    Mesh {
        /// The URDF.
        file: String,
        /// The link.
        link: String,
        /// The resolved file.
        path: String,
        /// What went wrong.
        message: String,
    },
    /// No link name was given and the file offers several (or none) for the role.
    #[error(
        "{file}: which {role}? give it by name; the file has {}",
        candidates_text(candidates)
    )]
    AmbiguousLink {
        /// The source.
        file: String,
        /// `"base link"` or `"tool link"`.
        role: &'static str,
        /// The links that could serve.
        candidates: Vec<String>,
    },
    /// The links below the tool link are not a parallel-jaw gripper the planner can model.
    #[error("{file}: below tool link `{tool_link}`: {reason}")]
    NotAJawGripper {
        /// The source.
        file: String,
        /// The tool link.
        tool_link: String,
        /// What is missing or not supported.
        reason: String,
    },
    /// No link of the arm has collision geometry: the planner cannot keep it clear.
    #[error(
        "{file}: no link of the arm {chain} has a <collision> element; the planner needs the \
         arm's collision geometry"
    )]
    NoCollisionGeometry {
        /// The source.
        file: String,
        /// The chain: "from `base` to `tool`".
        chain: String,
    },
    /// The arm's links do not fit in the link shapes the collision model holds, even with the
    /// links that move with one frame merged.
    #[error(
        "{file}: the arm has {count} links with collision geometry; merged per frame they \
         still need more than {max} shapes (link `{link}` does not fit)"
    )]
    TooManyLinkShapes {
        /// The source.
        file: String,
        /// The link (or merged links) left over.
        link: String,
        /// Links of the arm with pieces.
        count: usize,
        /// Most link shapes.
        max: usize,
    },
    /// A description larger than any robot: more links or joints, collision elements, or
    /// collision mesh bytes than [`crate::limits`] allows.
    #[error("{file}: {what}: more than the {max} a description may have")]
    TooLarge {
        /// The source.
        file: String,
        /// What there is too much of, with the count where known.
        what: String,
        /// The limit.
        max: String,
    },
    /// A joint asked to be held still cannot be.
    #[error("{file}: cannot hold joint `{joint}`: it {problem}")]
    HeldJoint {
        /// The source.
        file: String,
        /// The joint named.
        joint: String,
        /// What is wrong.
        problem: String,
    },
    /// The planner drives six joints; the chain, after holding joints, has another number.
    #[error(
        "{file}: the chain {chain} has {dof} actuated joints ({joints}); the planner drives \
         6{hint}"
    )]
    NotSixJoints {
        /// The source.
        file: String,
        /// The chain: "from `base` to `tool`".
        chain: String,
        /// How many it has.
        dof: usize,
        /// Their names.
        joints: String,
        /// What to do about it.
        hint: &'static str,
    },
}

/// `a`, `b` and `c` as "`a`, `b`, `c`" (or "none").
fn candidates_text(candidates: &[String]) -> String {
    if candidates.is_empty() {
        return "none".to_string();
    }
    candidates
        .iter()
        .map(|c| format!("`{c}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The searched directories, comma-separated (or "no directories").
fn searched_text(dirs: &[String]) -> String {
    let dirs: Vec<&str> = dirs
        .iter()
        .map(|d| if d.is_empty() { "." } else { d.as_str() })
        .collect();
    if dirs.is_empty() {
        return "no directories".to_string();
    }
    dirs.join(", ")
}
