//! Stage 6e, the lane body: the common path of a tick in SIMD lanes (`motion_lanes`) for a
//! mechanism or a scene (every closed-form kind has a lane kernel, Newton blocks `newton_block`):
//! the fused body's segments, built from the same DAG in the same order (so every lane computes
//! what the scalar tick computes), with the lane kernels in place of the scalar ones. The items
//! around it (`Lanes<L>`, `LaneTick<L>`) are [`crate::emit::lane_items`]'s.

use proc_macro2::{Ident, TokenStream};
use quote::{format_ident, quote};

use crate::analysis::Compiled;
use crate::analysis::closed_form::ClosedForm;
use crate::analysis::plan::BlockForms;
use crate::analysis::structure::BlockId;
use crate::emit::args::Args;
use crate::emit::body::{Builder, VarSource};
use crate::emit::cache::Cached;
use crate::ir::dag::Var;
use crate::sema::model::Kind;

/// Variables as `motion_lanes` reads them: the unknowns and their sines and cosines from the lane
/// state `st`, the params from the lanes' `self.params[i]`, the rest as the fused body does.
pub(crate) struct LaneVars<'a> {
    pub cached: &'a Cached<'a>,
    pub lane: &'a Ident,
}

impl VarSource for LaneVars<'_> {
    fn read(&self, v: Var) -> TokenStream {
        match v {
            Var::Q(i) => {
                let i = i as usize;
                quote!(st.q[#i])
            }
            Var::P(i) => {
                let i = i as usize;
                quote!(self.params[#i])
            }
            _ => self.cached.read(v),
        }
    }
    fn hint(&self, v: Var) -> String {
        self.cached.hint(v)
    }
    fn scalar(&self) -> &Ident {
        self.lane
    }
    fn trig(&self, v: Var) -> Option<TokenStream> {
        let src = self.cached.trig(v)?;
        Some(match v {
            Var::Q(i) => {
                let i = i as usize;
                quote!(st.sc[#i])
            }
            _ => src,
        })
    }
}

/// What a lane body computes: a mechanism's every block to order 2 with every point, or a
/// scene's subset (as [`crate::emit::motion::Subset`] for the scalar body).
pub(crate) struct LaneSubset<'a> {
    pub blocks: &'a [BlockId],
    pub order: u8,
    pub points: &'a [usize],
    /// Per unknown, whether its value is read (`ScenePlan::values_read`; `None`: all are). As
    /// the scalar scene body, a lane body with values to skip takes `every_angle: bool` (a tick
    /// passes `false`: an angle nobody reads is not computed; a start `true`).
    pub values_read: Option<&'a [bool]>,
    /// The length scale of lane `i` (Newton's tolerance is relative to it), an expression in `i`.
    pub scale_of: TokenStream,
}

/// Whether the common path of a tick of `blocks` runs in lanes: every block a closed form with
/// a lane kernel (every closed-form kind) or Newton; below order 2 (a scene estimating its
/// Newton blocks' rates by differences), closed forms only.
pub(crate) fn has_lane_path(c: &Compiled, blocks: &[BlockId], order: u8) -> bool {
    !blocks.is_empty() && (order >= 2 || blocks.iter().all(|&b| c.block(b).closed_form.is_some()))
}

/// `newton_block(…)` of a block without a closed form in lanes: its residual and Jacobian
/// (from the DAG, as `blockN_position` computes them) in a closure of the Newton state.
fn newton_call(c: &Compiled, vars: &LaneVars, rt: &TokenStream, bf: &BlockForms) -> TokenStream {
    let (m, dag, lt) = (&c.model, &c.system.dag, vars.lane);
    let k = bf.block.unknowns.len();
    let idx: Vec<usize> = bf.block.unknowns.iter().map(|u| u.index()).collect();
    let length: Vec<bool> = idx
        .iter()
        .map(|&u| m.unknowns[u].kind == Kind::Length)
        .collect();
    let q_trig = &vars.cached.q;
    let angle: Vec<bool> = idx.iter().map(|&u| q_trig[u]).collect();
    let mut roots = bf.residual.clone();
    roots.extend(bf.jacobian.iter().flatten());
    let mut b = Builder::new(dag, vars);
    let seg = b.segment(&roots);
    let (stmts, r) = (&seg.stmts, &seg.roots[..k]);
    let mut sets = TokenStream::new();
    for row in 0..k {
        for col in 0..k {
            if !dag.is_zero(bf.jacobian[row][col]) {
                let v = &seg.roots[k + row * k + col];
                sets.extend(quote!(jac[#row][#col] = #v;));
            }
        }
    }
    quote! {
        #rt::lanes::newton_block(st, [#(#idx),*], [#(#length),*], [#(#angle),*], scale, newton, report, ok,
            |st: &#rt::lanes::LaneTrig<#lt, _>| {
                #stmts
                let mut jac = [[#lt::zero(); #k]; #k];
                #sets
                ([#(#r),*], jac)
            });
    }
}

/// `fn motion_lanes(…)`: positions (the closed forms), each block's velocities and
/// accelerations from one factorization (up to the subset's order), then the points, in lanes.
pub(crate) fn motion_lanes(
    c: &Compiled,
    args: &Args,
    vars: &LaneVars,
    sub: &LaneSubset,
) -> TokenStream {
    let (rt, lt) = (&args.rt, vars.lane);
    let m = &c.model;
    let dag = &c.system.dag;
    let (ni, nu, _, npar) = crate::emit::args::sizes(m);
    let np = sub.points.len();
    // Whether a kernel computes angle `k`'s value: read, or (unread) when `every_angle` says so.
    let read = |k: usize| sub.values_read.is_none_or(|read| read[k]);
    let value = |k: usize| {
        if read(k) {
            quote!(true)
        } else {
            quote!(every_angle)
        }
    };
    let every_arg = sub.values_read.map(|_| quote!(every_angle: bool,));
    let mut b = Builder::new(dag, vars);
    let mut steps = TokenStream::new();
    let newton = sub.blocks.iter().any(|&b| c.block(b).closed_form.is_none());
    if newton {
        let scale_of = &sub.scale_of;
        steps.extend(quote!(let scale = #lt::from_fn(|i| #scale_of);));
    }
    for bf in sub.blocks.iter().map(|&b| c.block(b)) {
        let Some(cf) = &bf.closed_form else {
            steps.extend(newton_call(c, vars, rt, bf));
            continue;
        };
        let roots = cf.roots();
        let seg = b.segment(roots);
        let (stmts, r) = (&seg.stmts, &seg.roots);
        // A root that is the literal zero in the scalar call is `None`: the kernel takes the
        // scalar's zero path for it statically.
        let opt = |i: usize| {
            let v = &r[i];
            if dag.is_zero(roots[i]) {
                quote!(::core::option::Option::None)
            } else {
                quote!(::core::option::Option::Some(#v))
            }
        };
        let call = match cf {
            ClosedForm::Rrr(d) => {
                let (a, bb) = (d.a, d.b);
                let [kx, ky, pa, pb] = [0, 1, 2, 4].map(|i| &r[i]);
                let (ra, rb) = (opt(3), opt(5));
                if read(a) && read(bb) {
                    quote!(#rt::lanes::solve_dyad(st, #a, #bb, [#kx, #ky], (#pa, #ra), (#pb, #rb), newton.tolerance, &mut report.pivot_ratio, ok);)
                } else {
                    let (va, vb) = (value(a), value(bb));
                    quote!(#rt::lanes::solve_dyad_angles(st, (#a, #bb), [#kx, #ky], ((#pa, #ra), (#pb, #rb)), newton.tolerance, &mut report.pivot_ratio, ok, [#va, #vb]);)
                }
            }
            ClosedForm::Rpr { q, s, .. } => {
                let [kx, ky, mp, mr, np, nr] = [0, 1, 2, 3, 4, 5].map(|i| &r[i]);
                let v = value(*q);
                quote!(#rt::lanes::solve_rpr(st, (#q, #s), [#kx, #ky], (#mp, #mr), (#np, #nr), newton.tolerance, &mut report.pivot_ratio, ok, #v);)
            }
            ClosedForm::Rrp { q, s, .. } => {
                let [kx, ky, p, ux, uy] = [0, 1, 2, 4, 5].map(|i| &r[i]);
                let (rr, v) = (opt(3), value(*q));
                quote!(#rt::lanes::solve_rrp(st, (#q, #s), [#kx, #ky], (#p, #rr), [#ux, #uy], newton.tolerance, &mut report.pivot_ratio, ok, #v);)
            }
            ClosedForm::Linear2 { s1, s2, .. } => {
                let [kx, ky, ax, ay, bx, by] = [0, 1, 2, 3, 4, 5].map(|i| &r[i]);
                quote!(#rt::lanes::solve_linear2(st, (#s1, #s2), [#kx, #ky], [#ax, #ay], [#bx, #by], &mut report.pivot_ratio, ok);)
            }
            ClosedForm::Angle1 { q, .. } => {
                let (k, p, qq) = (&r[0], opt(1), &r[2]);
                let v = value(*q);
                quote!(#rt::lanes::solve_angle1(st, #q, #k, (#p, #qq), newton.tolerance, &mut report.pivot_ratio, ok, #v);)
            }
            ClosedForm::Length1 { s, .. } => {
                let (k, a) = (&r[0], &r[1]);
                quote!(#rt::lanes::solve_length1(st, #s, #k, #a, ok);)
            }
        };
        steps.extend(quote! {
            #stmts
            #call
        });
    }
    // Near a dead point the scalar refines in double words: such lanes leave the common path.
    steps.extend(quote! {
        *ok = *ok & !report.pivot_ratio.lt(#lt::lit(#rt::REFINE_BELOW));
    });
    for bf in sub
        .blocks
        .iter()
        .map(|&b| c.block(b))
        .filter(|_| sub.order >= 1)
    {
        let k = bf.block.unknowns.len();
        let idx = &bf.block.unknowns;
        let zi: Vec<usize> = (0..k).collect();
        let mut roots = bf.velocity_rhs.clone();
        roots.extend(bf.jacobian.iter().flatten());
        let seg = b.segment(&roots);
        let (stmts, rhs) = (&seg.stmts, &seg.roots[..k]);
        let mut sets = TokenStream::new();
        for r in 0..k {
            for cc in 0..k {
                if !dag.is_zero(bf.jacobian[r][cc]) {
                    let v = &seg.roots[k + r * k + cc];
                    sets.extend(quote!(jac[#r][#cc] = #v;));
                }
            }
        }
        steps.extend(quote! {
            #stmts
            let mut jac = [[#lt::zero(); #k]; #k];
            #sets
            let lu = #rt::lanes::factor_block(jac, ok);
            let z = lu.solve([#(#rhs),*], ok);
            #( qd[#idx] = z[#zi]; )*
        });
        if sub.order >= 2 {
            let acc = b.segment(&bf.acceleration_rhs);
            let (acc_stmts, acc_rhs) = (&acc.stmts, &acc.roots);
            steps.extend(quote! {
                #acc_stmts
                let z = lu.solve([#(#acc_rhs),*], ok);
                #( qdd[#idx] = z[#zi]; )*
            });
        }
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
    let zero = quote!(#lt::zero());
    let items = seg.roots.chunks(per).map(|p| {
        let at = |i: usize| p.get(i).unwrap_or(&zero);
        let (px, py, vx, vy, ax, ay) = (at(0), at(1), at(2), at(3), at(4), at(5));
        quote!(#rt::PointMotion { position: [#px, #py], velocity: [#vx, #vy], acceleration: [#ax, #ay] })
    });
    // `q̇`, `q̈` are written only by the rate stages the order reaches.
    let rate_let = |name: Ident, written: bool| {
        let m = written.then(|| quote!(mut));
        quote!(let #m #name = [#lt::zero(); #nu];)
    };
    let qd_let = rate_let(format_ident!("qd"), sub.order >= 1);
    let qdd_let = rate_let(format_ident!("qdd"), sub.order >= 2);
    quote! {
        /// The common path of a tick in lanes: every closed form from the last tick's branch,
        /// every Newton block from the predicted guess (a start: both from the guess), then
        /// velocities, accelerations and points, as the scalar tick computes them; lanes that
        /// leave it (a dead point, a large turn, a Newton step off the common path, a condition
        /// below the refinement threshold, a non-finite value) are cleared in `ok`.
        #[inline(always)]
        fn motion_lanes(&self, fixed: #rt::lanes::LaneFixed<'_, #lt, #ni, #npar>, st: &mut #rt::lanes::LaneTrig<#lt, #nu>,
            newton: &#rt::NewtonOptions<#lt::Scalar>, report: &mut #rt::lanes::LaneReport<#lt>, ok: &mut #lt::Mask,
            #every_arg)
            -> #rt::lanes::LaneRates<#lt, #nu, #np> {
            let #rt::lanes::LaneFixed { x, xd, xdd, tx, tp } = fixed;
            #qd_let
            #qdd_let
            #steps
            #stmts
            (qd, qdd, [#(#items),*])
        }
    }
}
