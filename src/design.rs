//! Design derivatives along a sweep: a solved row's dq/dp and dP/dp ([`sensitivity`], from
//! `DynMechanism::sensitivities`), the worst-case and root-sum-square deviation of every output
//! for given param tolerances ([`deviations`]), and the input effort that balances forces at the
//! points, by virtual work ([`input_effort`]). Sits on [`crate::sweep`]; the CLI's `sensitivity`,
//! `tolerance` and `sweep --load` print these.

use mechgen_runtime::{DynMechanism, Kind, MechanismInfo, SolveError};

use crate::sweep::SolvedRef;

/// The outputs a sensitivity has a row for, in order: each unknown, then `P_x`, `P_y` per point,
/// with their kinds.
pub fn outputs(info: &MechanismInfo) -> Vec<(String, Kind)> {
    let mut out: Vec<(String, Kind)> = info
        .unknowns
        .iter()
        .map(|u| (u.name.clone(), u.kind))
        .collect();
    for p in &info.points {
        out.push((format!("{p}_x"), Kind::Length));
        out.push((format!("{p}_y"), Kind::Length));
    }
    out
}

/// Every input's value at a row: the file's start values, the held ones, and `input` at `index`.
pub fn row_inputs(
    info: &MechanismInfo,
    index: usize,
    held: &[(usize, f64)],
    input: f64,
) -> Vec<f64> {
    let mut x: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
    for &(i, v) in held {
        x[i] = v;
    }
    x[index] = input;
    x
}

/// d(output)/dp at a solved position, row-major: one row per output of [`outputs`], one column
/// per param of `info.params`.
pub fn sensitivity(
    k: &dyn DynMechanism<f64>,
    info: &MechanismInfo,
    x: &[f64],
    q: &[f64],
) -> Result<Vec<f64>, SolveError> {
    let (nu, np, npar) = (info.unknowns.len(), info.points.len(), info.params.len());
    let mut s = vec![0.0; (nu + 2 * np) * npar];
    let (unknowns, points) = s.split_at_mut(nu * npar);
    k.sensitivities(x, q, unknowns, points)?;
    if s.iter().all(|v| v.is_finite()) {
        Ok(s)
    } else {
        Err(SolveError::Overflow {
            block: 0,
            stage: mechgen_runtime::Stage::Sensitivity,
        })
    }
}

/// One output's deviation for the given tolerances: worst case Σ |∂y/∂p| T and root-sum-square
/// √Σ (∂y/∂p T)².
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Deviation {
    pub worst: f64,
    pub rss: f64,
}

/// Every output's [`Deviation`] from a row's sensitivity `s` (as [`sensitivity`] gives it, with
/// `nparams` columns) and the tolerances `(param index, T)`.
pub fn deviations(s: &[f64], nparams: usize, tolerances: &[(usize, f64)]) -> Vec<Deviation> {
    s.chunks_exact(nparams.max(1))
        .map(|row| {
            let (mut worst, mut sq) = (0.0, 0.0);
            for &(p, t) in tolerances {
                let d = row.get(p).copied().unwrap_or(0.0) * t;
                worst += d.abs();
                sq += d * d;
            }
            Deviation {
                worst,
                rss: f64::sqrt(sq),
            }
        })
        .collect()
}

/// A force `(fx, fy)` on point `point` (index into `info.points`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Load {
    pub point: usize,
    pub force: [f64; 2],
}

/// The input torque (angle input: force × length per radian) or force (length input) that
/// balances `loads` at a solved row, by virtual work: −Σ (FX ∂P_x/∂x + FY ∂P_y/∂x), the points'
/// ∂P/∂x their velocities at the sweep's `rate` divided by it. `None` when the rate is zero (the
/// velocities then say nothing about ∂P/∂x).
pub fn input_effort(s: &SolvedRef<'_>, loads: &[Load], rate: f64) -> Option<f64> {
    if rate == 0.0 {
        return None;
    }
    let work: f64 = loads
        .iter()
        .filter_map(|l| {
            let v = s.points.get(l.point)?.velocity;
            Some(l.force[0] * v[0] + l.force[1] * v[1])
        })
        .sum();
    Some(-work / rate)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deviations_add_magnitudes_and_squares() {
        // Two outputs, three params; tolerances on params 0 and 2.
        let s = [1.0, 5.0, -2.0, 0.5, 0.0, 0.0];
        let d = deviations(&s, 3, &[(0, 0.1), (2, 0.2)]);
        assert!((d[0].worst - 0.5).abs() < 1e-15);
        assert!((d[0].rss - (0.01f64 + 0.16).sqrt()).abs() < 1e-15);
        assert_eq!(
            d[1],
            Deviation {
                worst: 0.05,
                rss: 0.05
            }
        );
    }
}
