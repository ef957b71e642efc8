//! Stage 6d: a mechanism's design derivatives, `sensitivities(x, q)` and `tick_sensitivities`:
//! J, Φp, ∂P/∂q and ∂P/∂p in one body on the sine and cosine caches (a tick's own, when it has
//! them), then dq/dp block by block, all params at once through each block's factored Jacobian
//! (`Factored::solve_columns`; the right-hand side's coupling to earlier blocks only where J has
//! an entry), and dP/dp = ∂P/∂p + ∂P/∂q dq/dp. The generic engine runs the same steps through the
//! runtime's `block_sensitivities` and `point_sensitivities`.

use proc_macro2::{Ident, TokenStream};
use quote::{format_ident, quote};

use crate::analysis::Compiled;
use crate::emit::args::{Args, equations_text};
use crate::emit::body::body;
use crate::emit::cache::{Cached, trig_masks};
use crate::emit::comments::comment;
use crate::ir::dag::{Dag, NodeId};

/// `entries` (rows × `cols`, row-major among `roots` from `at`) as an `SMatrix` named `name`,
/// its structural zeros left zero.
fn matrix(
    dag: &Dag,
    name: &Ident,
    entries: &[Vec<NodeId>],
    cols: usize,
    values: &[TokenStream],
    (rt, gt): (&TokenStream, &Ident),
) -> TokenStream {
    let rows = entries.len();
    let sets = entries.iter().enumerate().flat_map(|(r, row)| {
        row.iter()
            .enumerate()
            .filter(|(_, e)| !dag.is_zero(**e))
            .map(move |(k, _)| {
                let v = &values[r * cols + k];
                quote!(#name[(#r, #k)] = #v;)
            })
    });
    let sets: Vec<TokenStream> = sets.collect();
    let mutable = (!sets.is_empty()).then(|| quote!(mut));
    quote! {
        let #mutable #name = #rt::nalgebra::SMatrix::<#gt, #rows, #cols>::zeros();
        #(#sets)*
    }
}

/// `sensitivities`, `tick_sensitivities` and the fused `sensitivity_cached` they run (inside the
/// mechanism type's `impl<T: Real>` block).
pub(crate) fn sensitivity_fns(c: &Compiled, args: &Args) -> TokenStream {
    let (rt, gt, tick_ty) = (&args.rt, &args.items.scalar, &args.items.tick);
    let m = &c.model;
    let dag = &c.system.dag;
    let d = &c.derivatives;
    let (ni, nu, np, npar) = crate::emit::args::sizes(m);
    let rows = 2 * np;
    // J, Φp, ∂P/∂q and ∂P/∂p in one body: one set of products, the sines and cosines read from
    // the caches the caller passes.
    let (xm, qm, pm) = trig_masks(c);
    let cached = Cached {
        args,
        x: xm,
        q: qm,
        p: pm,
    };
    let per_point = |m: &[[Vec<NodeId>; 2]]| -> Vec<Vec<NodeId>> {
        m.iter().flat_map(|p| p.iter().cloned()).collect()
    };
    let (pq_rows, pp_rows) = (
        per_point(&d.point_jacobian),
        per_point(&d.point_param_jacobian),
    );
    let parts: [(&str, &[Vec<NodeId>], usize); 4] = [
        ("jac", &d.jacobian, nu),
        ("phi_p", &d.param_jacobian, npar),
        ("pq", &pq_rows, nu),
        ("pp", &pp_rows, npar),
    ];
    let roots: Vec<NodeId> = parts
        .iter()
        .flat_map(|(_, e, _)| e.iter().flatten().copied())
        .collect();
    let b = body(dag, &roots, &cached);
    let mut at = 0;
    let mut matrices = TokenStream::new();
    for (name, entries, cols) in parts {
        let n = entries.len() * cols;
        let name = format_ident!("{}", name);
        matrices.extend(matrix(
            dag,
            &name,
            entries,
            cols,
            &b.roots[at..at + n],
            (rt, gt),
        ));
        at += n;
    }
    let stmts = b.stmts;
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
        // Each row of the right-hand side: −Φp's row, less the earlier blocks' sensitivities
        // times the coupling entries of J (its structural zeros skipped).
        let rows = eqs.iter().map(|&e| {
            let coupling = (0..nu)
                .filter(|&j| !us.iter().any(|u| u.index() == j) && !dag.is_zero(d.jacobian[e][j]))
                .map(|j| quote!(- s.row(#j) * jac[(#e, #j)]));
            quote!(-phi_p.row(#e).into_owned() #(#coupling)*)
        });
        let sets = us
            .iter()
            .enumerate()
            .map(|(i, u)| quote!(s.set_row(#u, &z.row(#i));));
        blocks.extend(quote! {
            {
                let (eqs, us) = ([#(#eqs),*], [#(#us),*]);
                let lu = #rt::factor_block(#bi, #rt::Stage::Sensitivity,
                    #rt::nalgebra::SMatrix::<#gt, #k, #k>::from_fn(|i, j| jac[(eqs[i], us[j])]))?;
                let rhs = #rt::nalgebra::SMatrix::<#gt, #k, #npar>::from_rows(&[#(#rows),*]);
                let z = lu.solve_columns(#bi, #rt::Stage::Sensitivity, rhs)?;
                #(#sets)*
            }
        });
    }
    let ctx = quote!(tx: &[(#gt, #gt); #ni], tq: &[(#gt, #gt); #nu], tp: &[(#gt, #gt); #npar]);
    let ret = quote!(::core::result::Result<#rt::Sensitivities<#rt::nalgebra::SMatrix<#gt, #nu, #npar>,
        #rt::nalgebra::SMatrix<#gt, #rows, #npar>>, #rt::SolveError>);
    quote! {
        /// [`Self::sensitivities`] with the sines and cosines of the inputs, unknowns and params
        /// given.
        fn sensitivity_cached(&self, x: &[#gt; #ni], q: &[#gt; #nu], #ctx) -> #ret {
            #stmts
            #matrices
            let mut s = #rt::nalgebra::SMatrix::<#gt, #nu, #npar>::zeros();
            #blocks
            Ok(#rt::Sensitivities { unknowns: s, points: pp + pq * s })
        }

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
            let (tx, tp) = self.trig_fixed(x);
            let st = Self::trig_state(*q);
            self.sensitivity_cached(x, q, &tx, &st.sc, &tp)
        }

        /// [`Self::sensitivities`] at a tick's state, with the sines and cosines the tick keeps
        /// (when the params are still those of the last tick; else computed afresh).
        pub fn tick_sensitivities(&self, t: &#tick_ty<#gt>) -> #ret {
            use #rt::TickCache as _;
            if !t.same_params(&self.params.to_array()) {
                return self.sensitivities(&t.x, &t.q);
            }
            let (tx, tq) = t.trig();
            self.sensitivity_cached(&t.x, &t.q, tx, tq, t.params_trig())
        }
    }
}
