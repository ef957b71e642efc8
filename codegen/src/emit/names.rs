//! Stage 6 (emit), the names table: every Rust identifier the emitters introduce (locals of a
//! generated function, items of a mechanism's module) is allocated here, keyed by what it names,
//! never formed by gluing strings and hoping. A readable proposal (`v_q2`, `Params`) is used when it
//! is free; otherwise the table picks a documented alternative or the first free `PROPOSAL_N`.

use std::collections::{BTreeMap, BTreeSet};

use proc_macro2::Ident;
use quote::format_ident;

use crate::ir::dag::Var;

/// What a local of a generated function holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Local {
    /// A variable read from the arguments (input, unknown, param, or a rate of one).
    Value(Var),
    /// Its sine.
    Sin(Var),
    /// Its cosine.
    Cos(Var),
    /// The n-th intermediate of a straight-line body.
    Temp(usize),
    /// The sine of the n-th intermediate argument (not a variable) of a `sin_cos`.
    TempSin(usize),
    /// Its cosine.
    TempCos(usize),
}

/// Whether `s` is usable as a plain (non-raw) Rust identifier.
pub fn is_plain_ident(s: &str) -> bool {
    let mut chars = s.chars();
    let first_ok = chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_');
    first_ok
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
        && !crate::keywords::is_keyword(s)
}

/// One scope's identifiers: the reserved ones (arguments, fixed locals, other items) and those
/// allocated so far, each under its key.
#[derive(Clone, Debug, Default)]
pub struct Names<K: Ord> {
    taken: BTreeSet<String>,
    given: BTreeMap<K, Ident>,
}

impl<K: Ord + Copy> Names<K> {
    /// A table in which `reserved` are already taken.
    pub fn new<'a>(reserved: impl IntoIterator<Item = &'a str>) -> Self {
        Names {
            taken: reserved.into_iter().map(str::to_string).collect(),
            given: BTreeMap::new(),
        }
    }

    /// The identifier of `key`, allocated on first use: the first of `proposals` that is free,
    /// else the first free `{proposals[0]}_{n}`, n = 2, 3, … The same key always gets the same
    /// identifier; two keys never get the same one.
    pub fn get(&mut self, key: K, proposals: &[&str]) -> Ident {
        if let Some(id) = self.given.get(&key) {
            return id.clone();
        }
        let free = |s: &str, taken: &BTreeSet<String>| is_plain_ident(s) && !taken.contains(s);
        let base = proposals
            .first()
            .copied()
            .filter(|b| !b.is_empty())
            .unwrap_or("v");
        let chosen = proposals
            .iter()
            .find(|p| free(p, &self.taken))
            .map(|p| p.to_string())
            .unwrap_or_else(|| {
                (2usize..)
                    .map(|n| format!("{base}_{n}"))
                    .find(|s| free(s, &self.taken))
                    .unwrap_or_default()
            });
        self.taken.insert(chosen.clone());
        let id = format_ident!("{}", chosen);
        self.given.insert(key, id.clone());
        id
    }
}

/// The items of one mechanism's module that the emitters name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Item {
    /// The mechanism's type: the UpperCamelCase of its name.
    Type,
    /// The scalar type parameter of every generic item.
    Scalar,
    Params,
    Inputs,
    Unknowns,
    Points,
    Tick,
    Motion,
    /// A scene's outputs.
    Outputs,
    /// The lane type parameter of the lane items.
    LaneScalar,
    /// The mechanism in SIMD lanes, and its state between lane ticks.
    Lanes,
    LaneTick,
}

/// Proposals per item, in order: the mechanism's type takes its name first (the file names it);
/// an item whose usual name is that type's takes its alternative (`tick::Tick` is the mechanism
/// and `tick::TickState` the tick state; `params::ParamValues`, `t::S` for the scalar, …).
const ITEM_NAMES: &[(Item, &[&str])] = &[
    (Item::Scalar, &["T", "S"]),
    (Item::Params, &["Params", "ParamValues"]),
    (Item::Inputs, &["Inputs", "InputValues"]),
    (Item::Unknowns, &["Unknowns", "UnknownValues"]),
    (Item::Points, &["Points", "PointValues"]),
    (Item::Tick, &["Tick", "TickState"]),
    (Item::Motion, &["Motion", "MotionState"]),
    (Item::Outputs, &["Outputs", "OutputValues"]),
    (Item::LaneScalar, &["L", "W"]),
    (Item::Lanes, &["Lanes", "LaneSet"]),
    (Item::LaneTick, &["LaneTick", "LaneTickState"]),
];

/// The names of one mechanism module's items, all distinct.
#[derive(Clone, Debug)]
pub struct ModuleItems {
    pub ty: Ident,
    pub scalar: Ident,
    pub params: Ident,
    pub inputs: Ident,
    pub unknowns: Ident,
    pub points: Ident,
    pub tick: Ident,
    pub motion: Ident,
    pub outputs: Ident,
    pub lane_scalar: Ident,
    pub lanes: Ident,
    pub lane_tick: Ident,
}

impl ModuleItems {
    /// The items of the module of mechanism `name` (snake_case).
    pub fn new(name: &str) -> Self {
        let camel = upper_camel(name);
        // `Self`, the one keyword an UpperCamelCase name can be; the table then takes the second.
        let mut t: Names<Item> = Names::new(["Self", "V", "INFO", "POINT_NAMES"]);
        let ty = t.get(Item::Type, &[&camel, &format!("{camel}Mechanism")]);
        let mut get = |item: Item| {
            let proposals = ITEM_NAMES
                .iter()
                .find(|(i, _)| *i == item)
                .map(|(_, p)| *p)
                .unwrap_or(&[]);
            t.get(item, proposals)
        };
        ModuleItems {
            scalar: get(Item::Scalar),
            params: get(Item::Params),
            inputs: get(Item::Inputs),
            unknowns: get(Item::Unknowns),
            points: get(Item::Points),
            tick: get(Item::Tick),
            motion: get(Item::Motion),
            outputs: get(Item::Outputs),
            lane_scalar: get(Item::LaneScalar),
            lanes: get(Item::Lanes),
            lane_tick: get(Item::LaneTick),
            ty,
        }
    }
}

/// `four_bar` → `FourBar` (underscores dropped, each part capitalized).
pub fn upper_camel(name: &str) -> String {
    name.split('_')
        .filter(|s| !s.is_empty())
        .map(|s| {
            let mut c = s.chars();
            c.next()
                .map(|f| f.to_ascii_uppercase().to_string() + c.as_str())
                .unwrap_or_default()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_key_same_name_different_keys_different_names() {
        let mut n: Names<Local> = Names::new(["x", "q"]);
        let a = n.get(Local::Value(Var::Q(0)), &["v_a_d"]);
        let b = n.get(Local::Value(Var::Qd(1)), &["v_a_d"]);
        assert_eq!(a, "v_a_d");
        assert_eq!(b, "v_a_d_2");
        assert_eq!(n.get(Local::Value(Var::Q(0)), &["ignored"]), "v_a_d");
    }

    #[test]
    fn reserved_and_keywords_are_never_given() {
        let mut n: Names<Local> = Names::new(["jac", "v_a_2"]);
        assert_eq!(n.get(Local::Temp(0), &["jac"]), "jac_2");
        assert_eq!(n.get(Local::Temp(1), &["fn"]), "fn_2");
        assert_eq!(n.get(Local::Temp(2), &["v_a"]), "v_a");
        // `v_a_2` is reserved, so the next `v_a` is `v_a_3`.
        assert_eq!(n.get(Local::Temp(3), &["v_a"]), "v_a_3");
        assert_eq!(n.get(Local::Temp(4), &["Self", "SelfType"]), "SelfType");
    }

    #[test]
    fn alternatives_in_order() {
        let mut n: Names<u8> = Names::new(["Tick"]);
        assert_eq!(n.get(0, &["Tick", "TickState"]), "TickState");
        assert_eq!(n.get(1, &["Params", "ParamValues"]), "Params");
        let mut all = BTreeSet::new();
        for k in 2..40 {
            assert!(all.insert(n.get(k, &["Params"]).to_string()));
        }
    }

    #[test]
    fn module_items_never_clash_with_the_type() {
        let plain = ModuleItems::new("four_bar");
        assert_eq!(plain.ty, "FourBar");
        assert_eq!(plain.tick, "Tick");
        assert_eq!(plain.params, "Params");
        assert_eq!(plain.scalar, "T");
        let tick = ModuleItems::new("tick");
        assert_eq!(
            (tick.ty.to_string(), tick.tick.to_string()),
            ("Tick".into(), "TickState".into())
        );
        for (name, field) in [
            ("params", "ParamValues"),
            ("inputs", "InputValues"),
            ("unknowns", "UnknownValues"),
            ("points", "PointValues"),
            ("motion", "MotionState"),
            ("t", "S"),
        ] {
            let m = ModuleItems::new(name);
            let all = [
                &m.ty,
                &m.scalar,
                &m.params,
                &m.inputs,
                &m.unknowns,
                &m.points,
                &m.tick,
                &m.motion,
            ];
            assert!(all.iter().any(|i| *i == field), "{name}: {m:?}");
            let set: BTreeSet<String> = all.iter().map(|i| i.to_string()).collect();
            assert_eq!(set.len(), all.len(), "{name}: {m:?}");
        }
        assert_eq!(ModuleItems::new("self_").ty, "SelfMechanism");
        assert_eq!(upper_camel("a__long_name_2"), "ALongName2");
    }

    #[test]
    fn identifiers() {
        for ok in ["a", "a_d", "_x", "T", "q2", "fresh_tp"] {
            assert!(is_plain_ident(ok), "{ok}");
        }
        for bad in ["", "2a", "fn", "self", "Self", "a-b", "é", "_"] {
            assert!(!is_plain_ident(bad), "{bad}");
        }
    }
}
