//! The scene file's shape as serde reads it: one struct per table, every key optional (a
//! missing key is for the validation to name), and leaf types that refuse a value of the wrong
//! TOML type in the format's own words (`expected a number, found a string`). Key paths come
//! from `serde_path_to_error`, unknown keys from `serde_ignored`.

use std::fmt;
use std::marker::PhantomData;

use serde::de::value::MapAccessDeserializer;
use serde::de::{self, DeserializeOwned, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer};
use toml::Value;

use crate::text::clip;

#[derive(Deserialize)]
pub struct RawScene {
    pub name: Option<Str>,
    pub support: Option<Table<RawSupport>>,
    pub object: Option<Table<RawObject>>,
    pub grasps: Option<Table<RawGrasps>>,
    pub robot: Option<Robots>,
    pub planner: Option<Table<RawPlanner>>,
    pub physics: Option<Table<RawPhysics>>,
}

#[derive(Deserialize)]
pub struct RawSupport {
    pub height: Option<Num>,
}

#[derive(Deserialize)]
pub struct RawObject {
    pub mesh: Option<Str>,
    pub scale: Option<Num>,
    pub pose: Option<Table<RawPose>>,
    pub mass: Option<Num>,
}

/// `{ xyz = [..], rpy | rpy_deg | quat_xyzw = [..] }`.
#[derive(Deserialize)]
pub struct RawPose {
    pub xyz: Option<Nums<3>>,
    pub rpy: Option<Nums<3>>,
    pub rpy_deg: Option<Nums<3>>,
    pub quat_xyzw: Option<Nums<4>>,
}

#[derive(Deserialize)]
pub struct RawGrasps {
    pub power: Option<PosePair>,
    pub support: Option<Table<RawPose>>,
    /// Any value: the validation quotes a wrong one.
    pub mode: Option<Value>,
}

#[derive(Deserialize)]
pub struct RawRobot {
    pub name: Option<Str>,
    pub model: Option<Str>,
    pub urdf: Option<Str>,
    pub base_link: Option<Str>,
    pub tool_link: Option<Str>,
    pub hold: Option<Table<std::collections::BTreeMap<String, Num>>>,
    pub allow_collisions: Option<LinkPairs>,
    pub base: Option<Table<RawPose>>,
    pub start: Option<Nums<6>>,
    pub start_deg: Option<Nums<6>>,
    pub gripper: Option<Str>,
    pub precision_point_z: Option<Num>,
    pub power_point_z: Option<Num>,
}

#[derive(Deserialize)]
pub struct RawPlanner {
    pub support_distance: Option<Num>,
    pub min_axis_length: Option<Num>,
    pub step: Option<Num>,
    pub step_deg: Option<Num>,
    pub max_angle: Option<Num>,
    pub max_angle_deg: Option<Num>,
    pub weight_length: Option<Num>,
    pub weight_angle: Option<Num>,
    pub extra_steps: Option<Int>,
    pub min_grasp_axis_distance: Option<Num>,
    pub lift: Option<Num>,
    pub approach_distance: Option<Num>,
    pub max_joint_step: Option<Num>,
    pub max_joint_step_deg: Option<Num>,
    pub seed: Option<Int>,
    pub link_clearance: Option<Num>,
    pub finger_support_clearance: Option<Num>,
    pub robustness_samples: Option<Int>,
    pub robustness_pos: Option<Num>,
    pub robustness_yaw: Option<Num>,
    pub robustness_yaw_deg: Option<Num>,
    pub power_hold: Option<Str>,
}

/// The numeric keys are those of `PHYSICS_NUMBER_KEYS`.
#[derive(Deserialize)]
pub struct RawPhysics {
    pub mu_pad: Option<Num>,
    pub mu_support: Option<Num>,
    pub safety_factor: Option<Num>,
    pub pad_torsion_radius: Option<Num>,
    pub density: Option<Num>,
    pub max_twist_arm: Option<Num>,
    pub reject: Option<Flag>,
    pub reject_uncarried: Option<Flag>,
}

/// A finite number; an integer is taken as one.
pub struct Num(pub f64);
/// An integer.
pub struct Int(pub i64);
/// A string.
pub struct Str(pub String);
/// `true` or `false`.
pub struct Flag(pub bool);
/// An array of exactly `N` numbers.
pub struct Nums<const N: usize>(pub [f64; N]);
/// An array of `[link, link]` pairs (link names).
pub struct LinkPairs(pub Vec<[String; 2]>);
/// One `[link, link]` pair.
pub struct LinkPair(pub [String; 2]);
/// A table read as `T`.
pub struct Table<T>(pub T);
/// `grasps.power`: exactly two poses.
pub struct PosePair(pub [RawPose; 2]);
/// `[[robot]]`: exactly two tables.
pub struct Robots(pub [RawRobot; 2]);

/// Why the text is not a scene's shape.
pub enum RawError {
    /// Not TOML: the parser's message, on one line.
    Syntax(String),
    /// A key holds a value of the wrong type.
    Key { key: String, message: String },
}

/// Reads `text` into the file's shape, with the dotted path of every key the format does not
/// list (`robot[0].colour`) in key order: each table's keys alphabetically, depth first.
pub fn parse(text: &str) -> Result<(RawScene, Vec<String>), RawError> {
    let mut root: toml::Table = text.parse().map_err(|e: toml::de::Error| {
        // TOML quotes the offending line: a line of a binary or minified file can be
        // hundreds of kilobytes, so each quoted line is clipped.
        let lines: Vec<String> = e
            .to_string()
            .trim_end()
            .lines()
            .map(|l| clip(l, 160))
            .collect();
        RawError::Syntax(lines.join(" | "))
    })?;
    root.iter_mut().for_each(|(_, v)| mark_dates(v));
    let mut unknown = Vec::new();
    let mut note = |path: serde_ignored::Path| unknown.push(dotted(&path));
    let tracked = serde_ignored::Deserializer::new(Value::Table(root), &mut note);
    let raw = serde_path_to_error::deserialize(tracked).map_err(|e| RawError::Key {
        key: e.path().to_string(),
        message: e.inner().message().to_string(),
    })?;
    // A date where a table belongs is a table whose only key, toml's date key, went unread.
    if let Some(date) = unknown
        .iter()
        .find_map(|k| k.strip_suffix(&format!(".{DATE_KEY}")))
    {
        let (key, message) = (date.to_string(), "expected a table, found a date".into());
        return Err(RawError::Key { key, message });
    }
    Ok((raw, unknown))
}

/// How toml hands a date to serde: as a table with this one key (`toml_datetime`'s protocol).
const DATE_KEY: &str = "$__toml_private_datetime";

/// `toml::Value` hands a date to serde as its text, which a string key would take; as the table
/// toml's own reader makes of it, a date stays one: a leaf refuses it as "a date", and a
/// `toml::Value` (`grasps.mode`) reads it back as a date.
fn mark_dates(v: &mut Value) {
    match v {
        Value::Datetime(d) => {
            let text = Value::String(d.to_string());
            *v = Value::Table([(DATE_KEY.to_string(), text)].into_iter().collect());
        }
        Value::Array(a) => a.iter_mut().for_each(mark_dates),
        Value::Table(t) => t.iter_mut().for_each(|(_, v)| mark_dates(v)),
        _ => {}
    }
}

/// An ignored key's path as messages write it: `robot[0].base.colour`.
fn dotted(path: &serde_ignored::Path) -> String {
    use serde_ignored::Path as P;
    match path {
        P::Root => String::new(),
        P::Seq { parent, index } => format!("{}[{index}]", dotted(parent)),
        P::Map { parent, key } => match dotted(parent) {
            p if p.is_empty() => key.clone(),
            p => format!("{p}.{key}"),
        },
        P::Some { parent } | P::NewtypeStruct { parent } | P::NewtypeVariant { parent } => {
            dotted(parent)
        }
    }
}

/// A leaf: takes some TOML types, and refuses the others as "expected {expected}, found a
/// string". Each method takes one TOML type; by default it refuses it.
trait Accept: Sized {
    /// What the key holds, as messages say it ("a number").
    fn expected() -> String;
    fn refuse<E: de::Error>(found: &str) -> Result<Self, E> {
        let expected = Self::expected();
        Err(E::custom(format!("expected {expected}, found {found}")))
    }
    fn integer<E: de::Error>(_: i64) -> Result<Self, E> {
        Self::refuse("an integer")
    }
    fn float<E: de::Error>(_: f64) -> Result<Self, E> {
        Self::refuse("a float")
    }
    fn string<E: de::Error>(_: &str) -> Result<Self, E> {
        Self::refuse("a string")
    }
    fn boolean<E: de::Error>(_: bool) -> Result<Self, E> {
        Self::refuse("a boolean")
    }
    fn array<'de, A: SeqAccess<'de>>(_: A) -> Result<Self, A::Error> {
        Self::refuse("an array")
    }
    fn table<'de, A: MapAccess<'de>>(mut map: A) -> Result<Self, A::Error> {
        match map.next_key::<String>()?.as_deref() == Some(DATE_KEY) {
            true => Self::refuse("a date"),
            false => Self::refuse("a table"),
        }
    }
}

/// Exactly `N` elements; a wrong count is named before any element is read.
fn fixed<'de, A, T, const N: usize>(mut seq: A, count: &str) -> Result<[T; N], A::Error>
where
    A: SeqAccess<'de>,
    T: Deserialize<'de>,
{
    let wrong = |n| de::Error::custom(format!("expected {count}, found {n}"));
    if let Some(n) = seq.size_hint().filter(|&n| n != N) {
        return Err(wrong(n));
    }
    let mut items = Vec::with_capacity(N);
    while let Some(x) = seq.next_element()? {
        items.push(x);
    }
    let n = items.len();
    items.try_into().map_err(|_| wrong(n))
}

impl Accept for Num {
    fn expected() -> String {
        "a number".into()
    }
    fn integer<E: de::Error>(i: i64) -> Result<Self, E> {
        Ok(Num(i as f64))
    }
    fn float<E: de::Error>(x: f64) -> Result<Self, E> {
        match x.is_finite() {
            true => Ok(Num(x)),
            false => Err(E::custom(format!("number must be finite, found {x}"))),
        }
    }
}

impl Accept for Int {
    fn expected() -> String {
        "an integer".into()
    }
    fn integer<E: de::Error>(i: i64) -> Result<Self, E> {
        Ok(Int(i))
    }
}

impl Accept for Str {
    fn expected() -> String {
        "a string".into()
    }
    fn string<E: de::Error>(s: &str) -> Result<Self, E> {
        Ok(Str(s.to_string()))
    }
}

impl Accept for Flag {
    fn expected() -> String {
        "true or false".into()
    }
    fn boolean<E: de::Error>(b: bool) -> Result<Self, E> {
        Ok(Flag(b))
    }
}

impl Accept for LinkPair {
    fn expected() -> String {
        "a pair of link names".into()
    }
    fn array<'de, A: SeqAccess<'de>>(seq: A) -> Result<Self, A::Error> {
        let pair: [Str; 2] = fixed(seq, "2 link names")?;
        Ok(LinkPair(pair.map(|Str(s)| s)))
    }
}

impl Accept for LinkPairs {
    fn expected() -> String {
        "an array of [link, link] pairs".into()
    }
    fn array<'de, A: SeqAccess<'de>>(mut seq: A) -> Result<Self, A::Error> {
        let mut pairs = Vec::new();
        while let Some(LinkPair(p)) = seq.next_element()? {
            pairs.push(p);
        }
        Ok(LinkPairs(pairs))
    }
}

impl<const N: usize> Accept for Nums<N> {
    fn expected() -> String {
        format!("an array of {N} numbers")
    }
    fn array<'de, A: SeqAccess<'de>>(seq: A) -> Result<Self, A::Error> {
        let xs: [Num; N] = fixed(seq, &format!("{N} numbers"))?;
        Ok(Nums(xs.map(|Num(x)| x)))
    }
}

impl Accept for PosePair {
    fn expected() -> String {
        "an array of 2 poses".into()
    }
    fn array<'de, A: SeqAccess<'de>>(seq: A) -> Result<Self, A::Error> {
        let poses: [Table<RawPose>; 2] = fixed(seq, "exactly 2 poses")?;
        Ok(PosePair(poses.map(|Table(p)| p)))
    }
}

impl Accept for Robots {
    fn expected() -> String {
        "[[robot]] tables".into()
    }
    fn array<'de, A: SeqAccess<'de>>(seq: A) -> Result<Self, A::Error> {
        let robots: [Table<RawRobot>; 2] = fixed(seq, "exactly two [[robot]] tables")?;
        Ok(Robots(robots.map(|Table(r)| r)))
    }
}

impl<T: DeserializeOwned> Accept for Table<T> {
    fn expected() -> String {
        "a table".into()
    }
    fn table<'de, A: MapAccess<'de>>(map: A) -> Result<Self, A::Error> {
        T::deserialize(MapAccessDeserializer::new(map)).map(Table)
    }
}

/// The one visitor of every leaf: each TOML type goes to its method of [`Accept`].
struct Leaf<T>(PhantomData<T>);

impl<'de, T: Accept> Visitor<'de> for Leaf<T> {
    type Value = T;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(&T::expected())
    }
    fn visit_i64<E: de::Error>(self, i: i64) -> Result<T, E> {
        T::integer(i)
    }
    fn visit_f64<E: de::Error>(self, x: f64) -> Result<T, E> {
        T::float(x)
    }
    fn visit_str<E: de::Error>(self, s: &str) -> Result<T, E> {
        T::string(s)
    }
    fn visit_bool<E: de::Error>(self, b: bool) -> Result<T, E> {
        T::boolean(b)
    }
    fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<T, A::Error> {
        T::array(seq)
    }
    fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<T, A::Error> {
        T::table(map)
    }
}

macro_rules! deserialize_as_leaf {
    ($([$($generics:tt)*] $ty:ty),* $(,)?) => {$(
        impl<'de, $($generics)*> Deserialize<'de> for $ty {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                d.deserialize_any(Leaf(PhantomData))
            }
        }
    )*};
}

deserialize_as_leaf!(
    [] Num,
    [] Int,
    [] Str,
    [] Flag,
    [const N: usize] Nums<N>,
    [] LinkPair,
    [] LinkPairs,
    [] PosePair,
    [] Robots,
    [T: DeserializeOwned] Table<T>,
);
