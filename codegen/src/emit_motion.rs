//! Stage 6c: the fused motion solver of one mechanism (`motion_cached`), what a simulator tick
//! and `solve_arrays` run. All blocks' positions, then each block's velocities and accelerations
//! from one factorization of its Jacobian, then the points, written as segments of one
//! straight-line body ([`Builder`]): a product such as `l2·cos q2` is computed once for the loop
//! closure, the Jacobians, both right-hand sides and the points.

use proc_macro2::{Ident, TokenStream};
use quote::{format_ident, quote};

use crate::check::Kind;
use crate::compile::Compiled;
use crate::dag::Var;
use crate::emit::comment;
use crate::emit_body::{Builder, VarSource};

/// Variables as the fused body reads them: the unknowns and their sines and cosines from the
/// Newton state `st` (written block by block), everything else as the cached solvers do.
pub(crate) struct Fused<'a>(pub &'a dyn VarSource);

impl VarSource for Fused<'_> {
    fn read(&self, v: Var) -> TokenStream {
        match v {
            Var::Q(i) => {
                let i = i as usize;
                quote!(st.q[#i])
            }
            _ => self.0.read(v),
        }
    }
    fn hint(&self, v: Var) -> String {
        self.0.hint(v)
    }
    fn scalar(&self) -> &Ident {
        self.0.scalar()
    }
    fn trig(&self, v: Var) -> Option<TokenStream> {
        let src = self.0.trig(v)?;
        Some(match v {
            Var::Q(i) => {
                let i = i as usize;
                quote!(st.sc[#i])
            }
            _ => src,
        })
    }
}

/// What a fused body computes: the blocks (in solve order), the derivative order (0, 1, 2) and
/// the points; a mechanism's `motion_cached` takes everything, a scene its subset.
pub(crate) struct Subset<'a> {
    pub blocks: &'a [usize],
    pub order: u8,
    pub points: &'a [usize],
    /// The function's name and visibility (a scene's is called from its own module).
    pub name: Ident,
    pub vis: TokenStream,
}

/// `fn motion_cached(…) -> ::core::result::Result<(q̇, q̈, points), SolveError>`, inside the mechanism's impl.
pub(crate) fn motion(c: &Compiled, cached: &dyn VarSource, rt: &TokenStream) -> TokenStream {
    let blocks: Vec<usize> = (0..c.blocks.len()).collect();
    let points: Vec<usize> = (0..c.model.points.len()).collect();
    let sub = Subset {
        blocks: &blocks,
        order: 2,
        points: &points,
        name: format_ident!("motion_cached"),
        vis: TokenStream::new(),
    };
    motion_subset(c, cached, rt, &sub)
}

/// The fused body of `sub`: only its blocks, its derivative stages and its points (nodes that
/// nothing kept reaches are never emitted: segments take their roots' cones only).
pub(crate) fn motion_subset(
    c: &Compiled,
    cached: &dyn VarSource,
    rt: &TokenStream,
    sub: &Subset,
) -> TokenStream {
    let gt = cached.scalar();
    let m = &c.model;
    let dag = &c.system.dag;
    let (ni, nu, _, npar) = crate::emit::sizes(m);
    let np = sub.points.len();
    let fused = Fused(cached);
    let mut b = Builder::new(dag, &fused);
    let mut steps = TokenStream::new();
    for (bi, bf) in sub.blocks.iter().map(|&bi| (bi, &c.blocks[bi])) {
        let idx = &bf.block.unknowns;
        let lengths: Vec<bool> = idx
            .iter()
            .map(|&u| m.unknowns[u].kind == Kind::Length)
            .collect();
        let pos_fn = format_ident!("block{}_position", bi);
        let newton = quote! {
            #rt::newton_block(#bi, st, [#(#idx),*], [#(#lengths),*], self.params.length_scale(), options, report,
                |st| self.#pos_fn(x, &st.q, tx, tp, &st.sc))?;
        };
        match &bf.dyad {
            Some(d) => {
                let seg = b.segment(&d.roots);
                let stmts = &seg.stmts;
                let [kx, ky, pa, ra, pb, rb] = [0, 1, 2, 3, 4, 5].map(|i| &seg.roots[i]);
                let (a, bu) = (d.a, d.b);
                steps.extend(comment(&format!("Block {bi}: closed form (a dyad).")));
                steps.extend(quote! {
                    #stmts
                    if options.closed_forms {
                        #rt::solve_dyad(#bi, st, #a, #bu, [#kx, #ky], (#pa, #ra), (#pb, #rb),
                            || self.params.length_scale(), options.tolerance, report)?;
                    } else {
                        #newton
                    }
                });
            }
            None => {
                steps.extend(comment(&format!("Block {bi}: Newton.")));
                steps.extend(newton);
            }
        }
    }
    let rate_blocks = if sub.order >= 1 { sub.blocks } else { &[] };
    for (bi, bf) in rate_blocks.iter().map(|&bi| (bi, &c.blocks[bi])) {
        let k = bf.block.unknowns.len();
        let idx = &bf.block.unknowns;
        let zi: Vec<usize> = (0..k).collect();
        let mut roots = bf.velocity_rhs.clone();
        roots.extend(bf.jacobian.iter().flatten());
        let seg = b.segment(&roots);
        let (stmts, vel) = (&seg.stmts, &seg.roots[..k]);
        let sets = crate::emit_solve::jacobian_sets(c, bi, &seg.roots[k..]);
        steps.extend(comment(&format!(
            "Block {bi}: {}.",
            ["velocities", "velocities and accelerations"][usize::from(sub.order >= 2)]
        )));
        steps.extend(quote! {
            #stmts
            let mut jac = #rt::nalgebra::SMatrix::<#gt, #k, #k>::zeros();
            #sets
            let lu = #rt::factor_block(#bi, #rt::Stage::Velocity, jac)?;
            let z = lu.solve(#bi, #rt::Stage::Velocity, #rt::nalgebra::SVector::from([#(#vel),*]))?;
            #( qd[#idx] = z[#zi]; )*
        });
        if sub.order < 2 {
            continue;
        }
        let seg = b.segment(&bf.acceleration_rhs);
        let (stmts, acc) = (&seg.stmts, &seg.roots);
        steps.extend(quote! {
            #stmts
            let z = lu.solve(#bi, #rt::Stage::Acceleration, #rt::nalgebra::SVector::from([#(#acc),*]))?;
            #( qdd[#idx] = z[#zi]; )*
        });
    }
    let mut roots = Vec::new();
    let per = 2 * (usize::from(sub.order) + 1);
    for &p in sub.points {
        roots.extend(c.system.points[p]);
        if sub.order >= 1 {
            roots.extend(c.derivatives.point_velocity[p]);
        }
        if sub.order >= 2 {
            roots.extend(c.derivatives.point_acceleration[p]);
        }
    }
    let seg = b.segment(&roots);
    let stmts = &seg.stmts;
    let zero = quote!(#gt::zero());
    let items = seg.roots.chunks(per).map(|p| {
        let at = |i: usize| p.get(i).unwrap_or(&zero);
        let (px, py, vx, vy, ax, ay) = (at(0), at(1), at(2), at(3), at(4), at(5));
        quote!(#rt::PointMotion { position: [#px, #py], velocity: [#vx, #vy], acceleration: [#ax, #ay] })
    });
    steps.extend(comment("Points."));
    let (name, vis) = (&sub.name, &sub.vis);
    quote! {
        /// Positions block by block from the guess in `st`, then velocities and accelerations
        /// (each block's Jacobian factored once for both), then the points: one body, shared
        /// subexpressions computed once.
        #[inline(always)]
        #vis fn #name(&self, x: &[#gt; #ni], st: &mut #rt::TrigState<#gt, #nu>, tx: &[(#gt, #gt); #ni],
            tp: &[(#gt, #gt); #npar], xd: &[#gt; #ni], xdd: &[#gt; #ni], options: &#rt::NewtonOptions<#gt>,
            report: &mut #rt::NewtonReport<#gt>)
            -> ::core::result::Result<([#gt; #nu], [#gt; #nu], [#rt::PointMotion<#gt>; #np]), #rt::SolveError> {
            let mut qd = [#gt::zero(); #nu];
            let mut qdd = [#gt::zero(); #nu];
            #steps
            #stmts
            Ok((qd, qdd, [#(#items),*]))
        }
    }
}
