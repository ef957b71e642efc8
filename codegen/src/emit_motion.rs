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

/// The position solves of every block, in order, as segments of `b`: each closed-form block's
/// roots and its kernel (Newton when `options.closed_forms` is off), each other block's Newton.
fn position_steps(c: &Compiled, b: &mut Builder, rt: &TokenStream) -> TokenStream {
    let m = &c.model;
    let mut steps = TokenStream::new();
    for (bi, bf) in c.blocks.iter().enumerate() {
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
        match &bf.closed_form {
            Some(cf) => {
                let seg = b.segment(cf.roots());
                let stmts = &seg.stmts;
                let call = crate::emit_closed::kernel_call(rt, bi, cf, &seg.roots);
                let kind = crate::emit_closed::kind_text(cf);
                steps.extend(comment(&format!("Block {bi}: {kind}.")));
                steps.extend(quote! {
                    #stmts
                    if options.closed_forms {
                        #call
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
    steps
}

/// Which rates the rate steps solve: velocities (writing `qd`), accelerations (writing `qdd`,
/// reading `qd`), or both from one factorization per block.
#[derive(Clone, Copy, PartialEq)]
pub(crate) enum Rates {
    Velocity,
    Acceleration,
    Both,
}

/// Per block in order: its Jacobian factored once, then the velocity and/or acceleration solve.
fn rate_steps(
    c: &Compiled,
    b: &mut Builder,
    rt: &TokenStream,
    gt: &Ident,
    rates: Rates,
) -> TokenStream {
    let mut steps = TokenStream::new();
    let vel = rates != Rates::Acceleration;
    let stage = if vel {
        quote!(#rt::Stage::Velocity)
    } else {
        quote!(#rt::Stage::Acceleration)
    };
    for (bi, bf) in c.blocks.iter().enumerate() {
        let k = bf.block.unknowns.len();
        let idx = &bf.block.unknowns;
        let zi: Vec<usize> = (0..k).collect();
        let nv = if vel { k } else { 0 };
        let mut roots = if vel {
            bf.velocity_rhs.clone()
        } else {
            Vec::new()
        };
        roots.extend(bf.jacobian.iter().flatten());
        let seg = b.segment(&roots);
        let (stmts, rhs) = (&seg.stmts, &seg.roots[..nv]);
        let sets = crate::emit_solve::jacobian_sets(c, bi, &seg.roots[nv..]);
        let what = match rates {
            Rates::Velocity => "velocities",
            Rates::Acceleration => "accelerations",
            Rates::Both => "velocities and accelerations",
        };
        steps.extend(comment(&format!("Block {bi}: {what}.")));
        steps.extend(quote! {
            #stmts
            let mut jac = #rt::nalgebra::SMatrix::<#gt, #k, #k>::zeros();
            #sets
            let lu = #rt::factor_block(#bi, #stage, jac)?;
        });
        if vel {
            steps.extend(quote! {
                let z = lu.solve(#bi, #rt::Stage::Velocity, #rt::nalgebra::SVector::from([#(#rhs),*]))?;
                #( qd[#idx] = z[#zi]; )*
            });
        }
        if rates != Rates::Velocity {
            let seg = b.segment(&bf.acceleration_rhs);
            let (stmts, acc) = (&seg.stmts, &seg.roots);
            steps.extend(quote! {
                #stmts
                let z = lu.solve(#bi, #rt::Stage::Acceleration, #rt::nalgebra::SVector::from([#(#acc),*]))?;
                #( qdd[#idx] = z[#zi]; )*
            });
        }
    }
    steps
}

/// The standalone position, velocity and acceleration solvers (`position_cached`,
/// `velocity_cached`, `acceleration_cached`), from the same steps as the fused body, each
/// stopping at its derivative order; unknowns and their sines and cosines read from `st`.
pub(crate) fn stages(c: &Compiled, cached: &dyn VarSource, rt: &TokenStream) -> TokenStream {
    let gt = cached.scalar();
    let dag = &c.system.dag;
    let (ni, nu, _, npar) = crate::emit::sizes(&c.model);
    let fused = Fused(cached);
    let position = position_steps(c, &mut Builder::new(dag, &fused), rt);
    let velocity = rate_steps(c, &mut Builder::new(dag, &fused), rt, gt, Rates::Velocity);
    let acceleration = rate_steps(
        c,
        &mut Builder::new(dag, &fused),
        rt,
        gt,
        Rates::Acceleration,
    );
    quote! {
        /// Positions block by block from the guess in `st`.
        #[inline]
        fn position_cached(&self, x: &[#gt; #ni], st: &mut #rt::TrigState<#gt, #nu>, tx: &[(#gt, #gt); #ni],
            tp: &[(#gt, #gt); #npar], options: &#rt::NewtonOptions<#gt>, report: &mut #rt::NewtonReport<#gt>)
            -> ::core::result::Result<(), #rt::SolveError> {
            #position
            Ok(())
        }

        /// Velocities block by block at the solved position in `st`.
        #[inline]
        fn velocity_cached(&self, x: &[#gt; #ni], st: &#rt::TrigState<#gt, #nu>, tx: &[(#gt, #gt); #ni],
            tp: &[(#gt, #gt); #npar], xd: &[#gt; #ni]) -> ::core::result::Result<[#gt; #nu], #rt::SolveError> {
            let mut qd = [#gt::zero(); #nu];
            #velocity
            Ok(qd)
        }

        /// Accelerations block by block at the solved position in `st` and the rates `qd`.
        #[inline]
        fn acceleration_cached(&self, x: &[#gt; #ni], st: &#rt::TrigState<#gt, #nu>, tx: &[(#gt, #gt); #ni],
            tp: &[(#gt, #gt); #npar], xd: &[#gt; #ni], qd: &[#gt; #nu], xdd: &[#gt; #ni])
            -> ::core::result::Result<[#gt; #nu], #rt::SolveError> {
            let mut qdd = [#gt::zero(); #nu];
            #acceleration
            Ok(qdd)
        }
    }
}

/// `fn motion_cached(…) -> ::core::result::Result<(q̇, q̈, points), SolveError>`, inside the mechanism's impl.
pub(crate) fn motion(c: &Compiled, cached: &dyn VarSource, rt: &TokenStream) -> TokenStream {
    let gt = cached.scalar();
    let m = &c.model;
    let dag = &c.system.dag;
    let (ni, nu, np, npar) = crate::emit::sizes(m);
    let fused = Fused(cached);
    let mut b = Builder::new(dag, &fused);
    let mut steps = position_steps(c, &mut b, rt);
    steps.extend(rate_steps(c, &mut b, rt, gt, Rates::Both));
    let mut roots = Vec::new();
    for p in 0..np {
        roots.extend(c.system.points[p]);
        roots.extend(c.derivatives.point_velocity[p]);
        roots.extend(c.derivatives.point_acceleration[p]);
    }
    let seg = b.segment(&roots);
    let stmts = &seg.stmts;
    let items = seg.roots.chunks(6).map(|p| {
        let (px, py, vx, vy, ax, ay) = (&p[0], &p[1], &p[2], &p[3], &p[4], &p[5]);
        quote!(#rt::PointMotion { position: [#px, #py], velocity: [#vx, #vy], acceleration: [#ax, #ay] })
    });
    steps.extend(comment("Points."));
    quote! {
        /// Positions block by block from the guess in `st`, then velocities and accelerations
        /// (each block's Jacobian factored once for both), then the points: one body, shared
        /// subexpressions computed once.
        #[inline(always)]
        fn motion_cached(&self, x: &[#gt; #ni], st: &mut #rt::TrigState<#gt, #nu>, tx: &[(#gt, #gt); #ni],
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
