//! Lint: an angle param written as a plain number beyond a turn (`gam = 30`): radians are meant,
//! but such a value is almost always degrees, which a file writes `deg(30)` (as it does for a
//! start value, which the start lint checks against the loops).

use std::f64::consts::TAU;

use crate::diagnostic::Diagnostic;
use crate::sema::model::{Kind, Model};

/// A warning for each base param used as an angle whose plain value exceeds a turn.
pub fn degrees(model: &Model, diags: &mut Vec<Diagnostic>) {
    for p in &model.params {
        let v = p.value;
        if p.kind != Kind::Angle || p.source.is_some() || !v.is_finite() || v.abs() <= TAU {
            continue;
        }
        diags.push(
            Diagnostic::warning(
                p.name.span,
                format!(
                    "param `{}` = {v} is an angle, in radians: {:.1} turns",
                    p.name.text,
                    v / TAU
                ),
            )
            .with_label("an angle (it turns a vector in `e(…)` or feeds `sin`/`cos`)")
            .with_note(format!("an angle in degrees is written `deg({v})`")),
        );
    }
}
