//! Stage 6d: a mechanism's design derivatives, `sensitivities(x, q)`: dq/dp block by block
//! through each block's factored Jacobian and dP/dp for the points, by the runtime's
//! `block_sensitivities` and `point_sensitivities` on the whole-system matrices
//! (`jacobian`, `param_jacobian`, `point_jacobian`, `point_param_jacobian`).

use proc_macro2::TokenStream;
use quote::quote;

use crate::analysis::Compiled;
use crate::emit::{Args, comment, equations_text};

/// `sensitivities` and `tick_sensitivities` (inside the mechanism type's `impl<T: Real>` block).
pub(crate) fn sensitivity_fns(c: &Compiled, args: &Args) -> TokenStream {
    let (rt, gt, tick_ty) = (&args.rt, &args.items.scalar, &args.items.tick);
    let m = &c.model;
    let (ni, nu, np, npar) = crate::emit::sizes(m);
    let (ns, nps, rows) = (nu * npar, 2 * np * npar, 2 * np);
    let mut blocks = TokenStream::new();
    for (bi, bf) in c.blocks.iter().enumerate() {
        let k = bf.block.unknowns.len();
        let eqs: Vec<usize> = bf.block.equations.iter().map(|e| e.index()).collect();
        let us = &bf.block.unknowns;
        let names: Vec<&str> = us
            .iter()
            .map(|&u| m.unknowns[u.index()].name.text.as_str())
            .collect();
        blocks.extend(comment(&format!(
            "Block {bi}: {} in {}.",
            equations_text(&bf.block.equations),
            names.join(", ")
        )));
        blocks.extend(quote! {
            {
                let (eqs, us) = ([#(#eqs),*], [#(#us),*]);
                let lu = #rt::factor_block(#bi, #rt::Stage::Sensitivity,
                    #rt::nalgebra::SMatrix::<#gt, #k, #k>::from_fn(|i, j| jac[(eqs[i], us[j])]))?;
                #rt::block_sensitivities(#bi, &eqs, &us, &lu, |e, j| jac[(e, j)], |e, p| phi_p[(e, p)],
                    #npar, &mut s, &mut [#gt::zero(); #k])?;
            }
        });
    }
    let zeros = |n: usize| match n {
        0 => quote!([]),
        _ => quote!([#gt::zero(); #n]),
    };
    let (s_init, dp_init) = (zeros(ns), zeros(nps));
    quote! {
        /// The design derivatives at a solved position `(x, q)` (what a solve or a tick gave):
        /// dq/dp (a row per unknown) and dP/dp (rows `P_x`, `P_y` per point), one column per
        /// param of `Params` (derived params differentiated through), from J dq/dp = −Φp block
        /// by block. Non-finite arguments: `NonFinite`; a block singular there (a dead point,
        /// where they grow without bound): `Singular` at stage `Sensitivity`.
        pub fn sensitivities(&self, x: &[#gt; #ni], q: &[#gt; #nu])
            -> ::core::result::Result<#rt::Sensitivities<#rt::nalgebra::SMatrix<#gt, #nu, #npar>,
                #rt::nalgebra::SMatrix<#gt, #rows, #npar>>, #rt::SolveError> {
            #rt::check_finite(#rt::Quantity::Param, &self.params.to_array())?;
            #rt::check_finite(#rt::Quantity::Input, x)?;
            #rt::check_finite(#rt::Quantity::Position, q)?;
            let jac = self.jacobian(x, q);
            let phi_p = self.param_jacobian(x, q);
            let mut s: [#gt; #ns] = #s_init;
            #blocks
            let (pq, pp) = (self.point_jacobian(x, q), self.point_param_jacobian(x, q));
            let mut dp: [#gt; #nps] = #dp_init;
            #rt::point_sensitivities(|r, k| pq[(r, k)], |r, p| pp[(r, p)], &s, #nu, #npar, &mut dp);
            Ok(#rt::Sensitivities {
                unknowns: #rt::nalgebra::SMatrix::from_row_slice(&s),
                points: #rt::nalgebra::SMatrix::from_row_slice(&dp),
            })
        }

        /// [`Self::sensitivities`] at a tick's state.
        pub fn tick_sensitivities(&self, t: &#tick_ty<#gt>)
            -> ::core::result::Result<#rt::Sensitivities<#rt::nalgebra::SMatrix<#gt, #nu, #npar>,
                #rt::nalgebra::SMatrix<#gt, #rows, #npar>>, #rt::SolveError> {
            self.sensitivities(&t.x, &t.q)
        }
    }
}
