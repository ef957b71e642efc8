//! Stage 6c: the fused motion solver of one mechanism (`motion_cached`), what a simulator tick
//! and `solve_arrays` run. All blocks' positions, then each block's velocities and accelerations
//! from one factorization of its Jacobian, then the points, written as segments of one
//! straight-line body ([`Builder`]): a product such as `l2·cos q2` is computed once for the loop
//! closure, the Jacobians, both right-hand sides and the points.

use proc_macro2::{Ident, TokenStream};
use quote::{format_ident, quote};

use crate::analysis::Compiled;
use crate::analysis::structure::BlockId;
use crate::emit::body::{Builder, VarSource};
use crate::emit::closed::AngleValues;
use crate::emit::comments::comment;
use crate::ir::dag::Var;
use crate::sema::model::Kind;

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
fn position_steps(
    c: &Compiled,
    blocks: &[BlockId],
    b: &mut Builder,
    (rt, gt): (&TokenStream, &Ident),
    values: AngleValues,
    scale: &TokenStream,
) -> TokenStream {
    let m = &c.model;
    let mut steps = TokenStream::new();
    for (bi, bf) in blocks.iter().map(|&b| (b.index(), c.block(b))) {
        let idx = &bf.block.unknowns;
        let lengths: Vec<bool> = idx
            .iter()
            .map(|&u| m.unknowns[u.index()].kind == Kind::Length)
            .collect();
        let pos_fn = format_ident!("block{}_position", bi);
        let newton = quote! {
            #rt::newton_block(#bi, st, [#(#idx),*], [#(#lengths),*], #scale, &options.newton, report,
                |st| self.#pos_fn(x, &st.q, tx, tp, &st.sc))?;
        };
        match &bf.closed_form {
            Some(cf) => {
                let seg = b.segment(cf.roots());
                let stmts = &seg.stmts;
                let call = crate::emit::closed::kernel_call(rt, bi, cf, &seg.roots, values, scale);
                let kind = crate::emit::closed::kind_text(cf);
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
    steps.extend(comment(
        "Near a dead point: one Newton step per block with its residual in double words.",
    ));
    steps.extend(crate::emit::twofold::refine_step(blocks, rt, gt));
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
    blocks: &[BlockId],
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
    for (bi, bf) in blocks.iter().map(|&b| (b.index(), c.block(b))) {
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
        let sets = jacobian_sets(c, bi, &seg.roots[nv..]);
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
    let (ni, nu, _, npar) = crate::emit::args::sizes(&c.model);
    let fused = Fused(cached);
    let all: Vec<BlockId> = c.block_ids().collect();
    let position = position_steps(
        c,
        &all,
        &mut Builder::new(dag, &fused),
        (rt, gt),
        AngleValues::All,
        &quote!(self.params.length_scale()),
    );
    let velocity = rate_steps(
        c,
        &all,
        &mut Builder::new(dag, &fused),
        rt,
        gt,
        Rates::Velocity,
    );
    let acceleration = rate_steps(
        c,
        &all,
        &mut Builder::new(dag, &fused),
        rt,
        gt,
        Rates::Acceleration,
    );
    quote! {
        /// Positions block by block from the guess in `st`.
        #[inline]
        fn position_cached(&self, fixed: #rt::Fixed<'_, #gt, #ni, #npar>, st: &mut #rt::TrigState<#gt, #nu>,
            options: &#rt::SolveOptions<#gt>, report: &mut #rt::NewtonReport<#gt>)
            -> ::core::result::Result<(), #rt::SolveError> {
            let #rt::Fixed { x, xd, xdd, tx, tp } = fixed;
            #position
            Ok(())
        }

        /// Velocities block by block at the solved position in `st`.
        #[inline]
        fn velocity_cached(&self, fixed: #rt::Fixed<'_, #gt, #ni, #npar>, st: &#rt::TrigState<#gt, #nu>)
            -> ::core::result::Result<[#gt; #nu], #rt::SolveError> {
            let #rt::Fixed { x, xd, xdd, tx, tp } = fixed;
            let mut qd = [#gt::zero(); #nu];
            #velocity
            Ok(qd)
        }

        /// Accelerations block by block at the solved position in `st` and the rates `qd`.
        #[inline]
        fn acceleration_cached(&self, fixed: #rt::Fixed<'_, #gt, #ni, #npar>, st: &#rt::TrigState<#gt, #nu>,
            qd: &[#gt; #nu]) -> ::core::result::Result<[#gt; #nu], #rt::SolveError> {
            let #rt::Fixed { x, xd, xdd, tx, tp } = fixed;
            let mut qdd = [#gt::zero(); #nu];
            #acceleration
            Ok(qdd)
        }
    }
}

/// What a fused body computes: the blocks (in solve order), the derivative order (0, 1, 2) and
/// the points; a mechanism's `motion_cached` takes everything, a scene its subset.
pub(crate) struct Subset<'a> {
    pub blocks: &'a [BlockId],
    pub order: u8,
    pub points: &'a [usize],
    /// The function's name and visibility (a scene's is called from its own module).
    pub name: Ident,
    pub vis: TokenStream,
    /// Per unknown, whether its value is read (`ScenePlan::values_read`); `None`: all are. A
    /// scene's body then takes an `every_angle: bool` argument, and its dyads compute the angles
    /// nobody reads only when it is true (the scene's `solve` passes true, its `tick` false).
    pub values_read: Option<&'a [bool]>,
    /// The length scale Newton's tolerance and a gap's report are relative to: the params'
    /// `length_scale()`, or a scene's own over the params it reads.
    pub length_scale: TokenStream,
    /// Also every body's mass properties and motion, after the points and sharing their
    /// subexpressions (`tick_dynamics_arrays`): the body then hands them to a `BodySink`.
    pub bodies: bool,
}

/// `fn motion_cached(…) -> ::core::result::Result<(q̇, q̈, points), SolveError>`, inside the mechanism's impl.
pub(crate) fn motion(c: &Compiled, cached: &dyn VarSource, rt: &TokenStream) -> TokenStream {
    let blocks: Vec<BlockId> = c.block_ids().collect();
    let points: Vec<usize> = (0..c.model.points.len()).collect();
    let sub = Subset {
        blocks: &blocks,
        order: 2,
        points: &points,
        name: format_ident!("motion_cached"),
        vis: TokenStream::new(),
        values_read: None,
        length_scale: quote!(self.params.length_scale()),
        bodies: false,
    };
    let plain = motion_subset(c, cached, rt, &sub);
    if c.system.bodies.is_empty() && c.system.gravity.is_none() {
        return plain;
    }
    let with_bodies = Subset {
        name: format_ident!("motion_bodies_cached"),
        bodies: true,
        ..sub
    };
    let bodies = motion_subset(c, cached, rt, &with_bodies);
    quote!(#plain #bodies)
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
    let (ni, nu, _, npar) = crate::emit::args::sizes(m);
    let np = sub.points.len();
    let fused = Fused(cached);
    let mut b = Builder::new(dag, &fused);
    let every = quote!(every_angle);
    let values = match sub.values_read {
        Some(read) => AngleValues::Read {
            read,
            every: &every,
        },
        None => AngleValues::All,
    };
    let mut steps = position_steps(c, sub.blocks, &mut b, (rt, gt), values, &sub.length_scale);
    let every_arg = sub.values_read.map(|_| quote!(every_angle: bool,));
    let rates = [None, Some(Rates::Velocity), Some(Rates::Both)][usize::from(sub.order.min(2))];
    if let Some(rates) = rates {
        steps.extend(rate_steps(c, sub.blocks, &mut b, rt, gt, rates));
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
    let point_roots = roots.len();
    if sub.bodies {
        roots.extend(crate::emit::bodies::body_roots(c).0);
    }
    let seg = b.segment(&roots);
    let stmts = &seg.stmts;
    let (point_exprs, body_exprs) = seg.roots.split_at(point_roots);
    let zero = quote!(#gt::zero());
    let items = point_exprs.chunks(per).map(|p| {
        let at = |i: usize| p.get(i).unwrap_or(&zero);
        let (px, py, vx, vy, ax, ay) = (at(0), at(1), at(2), at(3), at(4), at(5));
        quote!(#rt::PointMotion { position: [#px, #py], velocity: [#vx, #vy], acceleration: [#ax, #ay] })
    });
    steps.extend(comment("Points."));
    let (name, vis) = (&sub.name, &sub.vis);
    // `q̇`, `q̈` are written only by the rate stages the order reaches.
    let rate_let = |name: Ident, written: bool| {
        let m = written.then(|| quote!(mut));
        quote!(let #m #name = [#gt::zero(); #nu];)
    };
    let qd_let = rate_let(format_ident!("qd"), sub.order >= 1);
    let qdd_let = rate_let(format_ident!("qdd"), sub.order >= 2);
    // With bodies: a sink they are handed to after the points.
    let (generics, body_args, body_calls) = if sub.bodies {
        (
            quote!(<S: #rt::BodySink<#gt>>),
            quote!(sink: &mut S,),
            crate::emit::bodies::body_sink_calls(c, (rt, gt), body_exprs),
        )
    } else {
        (TokenStream::new(), TokenStream::new(), TokenStream::new())
    };
    quote! {
        /// Positions block by block from the guess in `st`, then velocities and accelerations
        /// (each block's Jacobian factored once for both), then the points: one body, shared
        /// subexpressions computed once.
        #[inline(always)]
        #vis fn #name #generics(&self, fixed: #rt::Fixed<'_, #gt, #ni, #npar>, st: &mut #rt::TrigState<#gt, #nu>,
            options: &#rt::SolveOptions<#gt>, report: &mut #rt::NewtonReport<#gt>, #every_arg #body_args)
            -> ::core::result::Result<#rt::Rates<#gt, #nu, #np>, #rt::SolveError> {
            let #rt::Fixed { x, xd, xdd, tx, tp } = fixed;
            #qd_let
            #qdd_let
            #steps
            #stmts
            #body_calls
            Ok((qd, qdd, [#(#items),*]))
        }
    }
}

/// `jac[(r, c)] = …;` for the structurally non-zero entries of block `bi`'s Jacobian, each under a
/// comment naming the J entry; `roots` holds the entries' expressions row by row.
pub(crate) fn jacobian_sets(c: &Compiled, bi: usize, roots: &[TokenStream]) -> TokenStream {
    let (m, dag, bf) = (&c.model, &c.system.dag, &c.blocks[bi]);
    let k = bf.block.unknowns.len();
    let mut sets = TokenStream::new();
    for r in 0..k {
        for cc in 0..k {
            if dag.is_zero(bf.jacobian[r][cc]) {
                continue;
            }
            let v = &roots[r * k + cc];
            let (eq, un) = (bf.block.equations[r].index(), bf.block.unknowns[cc]);
            sets.extend(comment(&format!(
                "J[{eq}][{}] = ∂Φ{eq}/∂{}",
                un.index(),
                m.unknowns[un.index()].name.text
            )));
            sets.extend(quote!(jac[(#r, #cc)] = #v;));
        }
    }
    sets
}
