//! What a mechanism is made of, as data: [`StaticInfo`] (compiled into generated code) and
//! [`MechanismInfo`] (owned, for mechanisms loaded at run time), with the descriptions of their
//! coordinates and params, [`PointMotion`], and a body's [`BodyMotion`] and [`BodyMass`].

use alloc::string::{String, ToString};
use alloc::vec::Vec;

/// Angle (radians) or length (file units), as inferred from the file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Kind {
    Angle,
    Length,
}

/// An input or unknown of a generated mechanism: its name, kind and value in the file's `start`
/// configuration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoordInfo {
    pub name: &'static str,
    pub kind: Kind,
    pub start: f64,
}

/// A param of a generated mechanism and its default (the file's value).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamInfo {
    pub name: &'static str,
    pub kind: Kind,
    pub default: f64,
}

/// Everything static about a generated mechanism.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StaticInfo {
    pub name: &'static str,
    pub description: &'static str,
    pub inputs: &'static [CoordInfo],
    pub unknowns: &'static [CoordInfo],
    pub params: &'static [ParamInfo],
    pub points: &'static [&'static str],
    /// Unknown indices of each diagonal block, in solve order.
    pub blocks: &'static [&'static [usize]],
    /// Whether each block is solved in closed form (on its guess's side: a tick with closed
    /// forms on cannot leave the branch there); else by Newton.
    pub closed: &'static [bool],
    /// The moving bodies (`[mechanism.NAME.bodies.B]`, file order), for dynamics; empty without.
    pub bodies: &'static [&'static str],
}

/// An input or unknown, owned: its name, kind and value in the file's `start` configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct CoordDesc {
    pub name: String,
    pub kind: Kind,
    pub start: f64,
}

/// A param, owned: its name, kind and value (the file's, or the one a loader was given).
#[derive(Clone, Debug, PartialEq)]
pub struct ParamDesc {
    pub name: String,
    pub kind: Kind,
    pub value: f64,
}

/// An owned description of a mechanism (generated or loaded at run time): what the object-safe
/// [`crate::DynMechanism::info`] returns.
#[derive(Clone, Debug, PartialEq)]
pub struct MechanismInfo {
    pub name: String,
    pub description: String,
    pub inputs: Vec<CoordDesc>,
    pub unknowns: Vec<CoordDesc>,
    pub params: Vec<ParamDesc>,
    pub points: Vec<String>,
    /// Unknown indices of each diagonal block, in solve order.
    pub blocks: Vec<Vec<usize>>,
    /// Whether each block is solved in closed form (else by Newton).
    pub closed: Vec<bool>,
    /// The moving bodies, in file order (empty: no dynamics).
    pub bodies: Vec<String>,
}

impl From<&CoordInfo> for CoordDesc {
    fn from(c: &CoordInfo) -> Self {
        CoordDesc {
            name: c.name.to_string(),
            kind: c.kind,
            start: c.start,
        }
    }
}

impl From<&ParamInfo> for ParamDesc {
    fn from(p: &ParamInfo) -> Self {
        ParamDesc {
            name: p.name.to_string(),
            kind: p.kind,
            value: p.default,
        }
    }
}

/// The description of a generated mechanism, made from its static info once per process (kept
/// for the process: one per compiled-in mechanism type), so that a sweep's start reads it without
/// allocating.
#[cfg(feature = "std")]
pub fn shared(info: &'static StaticInfo) -> &'static MechanismInfo {
    use std::sync::Mutex;
    static SHARED: Mutex<Vec<(usize, &'static MechanismInfo)>> = Mutex::new(Vec::new());
    let key = info as *const StaticInfo as usize;
    let mut made = SHARED
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    if let Some(&(_, m)) = made.iter().find(|(k, _)| *k == key) {
        return m;
    }
    let m: &'static MechanismInfo = alloc::boxed::Box::leak(alloc::boxed::Box::new(info.into()));
    made.push((key, m));
    m
}

impl From<&StaticInfo> for MechanismInfo {
    fn from(s: &StaticInfo) -> Self {
        MechanismInfo {
            name: s.name.to_string(),
            description: s.description.to_string(),
            inputs: s.inputs.iter().map(CoordDesc::from).collect(),
            unknowns: s.unknowns.iter().map(CoordDesc::from).collect(),
            params: s.params.iter().map(ParamDesc::from).collect(),
            points: s.points.iter().map(|p| p.to_string()).collect(),
            blocks: s.blocks.iter().map(|b| b.to_vec()).collect(),
            closed: s.closed.to_vec(),
            bodies: s.bodies.iter().map(|b| b.to_string()).collect(),
        }
    }
}

/// A point's position, velocity and acceleration (laid out as six `T` in this order: run-time
/// compiled code writes them so).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct PointMotion<T> {
    pub position: [T; 2],
    pub velocity: [T; 2],
    pub acceleration: [T; 2],
}

/// A body's motion: its centre of mass (position, velocity, acceleration) and its angle with
/// the angle's first and second time derivatives.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyMotion<T> {
    pub com: PointMotion<T>,
    /// φ, φ̇, φ̈.
    pub angle: [T; 3],
}

/// A body's mass and its moment of inertia about its centre of mass (the file's units).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyMass<T> {
    pub mass: T,
    pub inertia: T,
}
