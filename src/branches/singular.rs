//! Branch identification, singular configurations: a dead point refined as the solution of the
//! bordered system (Φ(q, x) = 0 and g(q, x) = 0, where g is the bordered matrix's last entry and
//! vanishes exactly where J is singular), so that both its input and its configuration are good
//! to rounding level (bisection on the count finds the input, but near a fold q moves like the
//! square root of the input, so the bisected configuration is only good to about 1e-8).

use mechgen_codegen::Compiled;
use mechgen_runtime::nalgebra::{DMatrix, DVector};

use crate::generic::tape::{Env, Tape};

/// The residuals, J and Φx of the whole mechanism as tapes.
#[derive(Clone, Debug)]
pub(super) struct Tapes {
    residual: Tape,
    jacobian: Tape,
    input_jacobian: Tape,
    n: usize,
    inputs: usize,
}

/// What the bordered system needs at one point `(x, q)`.
struct Local {
    residual: DVector<f64>,
    jacobian: DMatrix<f64>,
    /// ∂Φ/∂x for the analysed input.
    input_column: DVector<f64>,
}

impl Tapes {
    pub(super) fn new(c: &Compiled) -> Tapes {
        let d = &c.derivatives;
        let dag = &c.system.dag;
        let flat = |rows: &[Vec<_>]| rows.iter().flatten().copied().collect::<Vec<_>>();
        Tapes {
            residual: Tape::new(dag, &c.system.residuals),
            jacobian: Tape::new(dag, &flat(&d.jacobian)),
            input_jacobian: Tape::new(dag, &flat(&d.input_jacobian)),
            n: c.model.unknowns.len(),
            inputs: c.model.inputs.len(),
        }
    }

    fn local(&self, x: &[f64], input: usize, q: &[f64], p: &[f64]) -> Local {
        let n = self.n;
        let env = Env::position(x, q, p);
        let mut regs = Vec::new();
        let mut r = vec![0.0; n];
        self.residual.eval_or_nan(&env, &mut regs, &mut r);
        let mut j = vec![0.0; n * n];
        self.jacobian.eval_or_nan(&env, &mut regs, &mut j);
        let mut jx = vec![0.0; n * self.inputs];
        self.input_jacobian.eval_or_nan(&env, &mut regs, &mut jx);
        Local {
            residual: DVector::from_vec(r),
            jacobian: DMatrix::from_row_slice(n, n, &j),
            input_column: DVector::from_fn(n, |i, _| jx[i * self.inputs + input]),
        }
    }
}

/// The bordered matrix `[[J, b], [cᵀ, 0]]`.
fn bordered(j: &DMatrix<f64>, b: &DVector<f64>, c: &DVector<f64>) -> DMatrix<f64> {
    let n = j.nrows();
    let mut m = DMatrix::zeros(n + 1, n + 1);
    m.view_mut((0, 0), (n, n)).copy_from(j);
    m.view_mut((0, n), (n, 1)).copy_from(b);
    m.view_mut((n, 0), (1, n)).copy_from(&c.transpose());
    m
}

/// `g` and the right and left null vectors `v`, `w` of the bordered system at `j`:
/// `[[J, b], [cᵀ, 0]] [v; g] = [0; 1]` and the same with the transpose for `w`.
fn border(
    j: &DMatrix<f64>,
    b: &DVector<f64>,
    c: &DVector<f64>,
) -> Option<(f64, DVector<f64>, DVector<f64>)> {
    let n = j.nrows();
    let m = bordered(j, b, c);
    let e = DVector::from_fn(n + 1, |i, _| if i == n { 1.0 } else { 0.0 });
    let lu = m.clone().lu();
    let right = lu.solve(&e)?;
    let left = m.transpose().lu().solve(&e)?;
    let g = right[n];
    Some((
        g,
        right.rows(0, n).into_owned(),
        left.rows(0, n).into_owned(),
    ))
}

/// Inputs `x` with the analysed one set to `value`.
fn with_input(x: &[f64], input: usize, value: f64) -> Vec<f64> {
    let mut x = x.to_vec();
    x[input] = value;
    x
}

impl Tapes {
    /// The dead point near `(x0, q0)`: Newton on the bordered system in `(q, x)` from there.
    /// `scale` weighs length unknowns and a length input (`angle` per unknown, `input_angle`).
    /// `None` when J is not close to singular there or Newton does not settle near the start.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn fold(
        &self,
        inputs: &[f64],
        input: usize,
        x0: f64,
        q0: &[f64],
        p: &[f64],
        weights: &[f64],
    ) -> Option<(f64, Vec<f64>)> {
        let n = self.n;
        if n == 0 {
            return None;
        }
        // The borders: J's singular vectors for its smallest singular value at the start.
        let start = self.local(&with_input(inputs, input, x0), input, q0, p);
        let svd = start.jacobian.clone().svd(true, true);
        let k = svd.singular_values.imin();
        let b = svd.u.as_ref()?.column(k).into_owned();
        let c = svd.v_t.as_ref()?.row(k).transpose();
        let (mut x, mut q) = (x0, q0.to_vec());
        // The size of a step in the unknowns' own units (lengths relative to the scale).
        let size = |dz: &DVector<f64>| {
            dz.iter()
                .zip(weights)
                .map(|(d, w)| (d * w).abs())
                .fold(0.0, f64::max)
        };
        let mut settled = 0;
        for _ in 0..40 {
            let xs = with_input(inputs, input, x);
            let l = self.local(&xs, input, &q, p);
            let (g, v, w) = border(&l.jacobian, &b, &c)?;
            // ∂g/∂z = −wᵀ (∂J/∂z) v, with ∂J/∂z · v by central differences.
            let mut grad = DVector::zeros(n + 1);
            for k in 0..=n {
                let z = if k < n { q[k] } else { x };
                let h = 1e-6 * (1.0 + z.abs());
                let jv = |s: f64| {
                    let (mut qs, mut xs) = (q.clone(), x);
                    if k < n {
                        qs[k] += s;
                    } else {
                        xs += s;
                    }
                    let jm = self
                        .local(&with_input(inputs, input, xs), input, &qs, p)
                        .jacobian;
                    jm * &v
                };
                let d = (jv(h) - jv(-h)) / (2.0 * h);
                grad[k] = -w.dot(&d);
            }
            let mut a = DMatrix::zeros(n + 1, n + 1);
            a.view_mut((0, 0), (n, n)).copy_from(&l.jacobian);
            a.view_mut((0, n), (n, 1)).copy_from(&l.input_column);
            a.view_mut((n, 0), (1, n + 1)).copy_from(&grad.transpose());
            let mut rhs = DVector::zeros(n + 1);
            rhs.rows_mut(0, n).copy_from(&(-&l.residual));
            rhs[n] = -g;
            let dz = a.lu().solve(&rhs)?;
            if !dz.iter().all(|d| d.is_finite()) {
                return None;
            }
            for k in 0..n {
                q[k] += dz[k];
            }
            x += dz[n];
            if size(&dz) <= 1e-14 {
                settled += 1;
                if settled == 2 {
                    break;
                }
            }
        }
        let moved = q
            .iter()
            .zip(q0)
            .zip(weights)
            .map(|((a, b), w)| ((a - b) * w).abs())
            .fold(((x - x0) * weights[n]).abs(), f64::max);
        (settled > 0 && moved <= 1e-5).then_some((x, q))
    }
}
