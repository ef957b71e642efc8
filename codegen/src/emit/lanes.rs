//! Stage 6e: a mechanism in SIMD lanes: `Lanes<L>` (W instances, each with its own params) and
//! `LaneTick<L>`, ticked by the runtime's lane driver. A mechanism whose blocks all have lane
//! kernels (dyads, RPR, one angle, one length) gets the common path of its tick in lanes (`motion_lanes`): the fused body's segments, built
//! from the same DAG in the same order (so every lane computes what the scalar tick computes),
//! with the lane kernels in place of the scalar ones; every other lane (and every lane of any
//! other mechanism) is ticked by the scalar tick.

use proc_macro2::{Ident, TokenStream};
use quote::quote;

use crate::analysis::Compiled;
use crate::analysis::closed_form::ClosedForm;
use crate::emit::Args;
use crate::emit::body::{Builder, VarSource};
use crate::emit::cache::{Cached, trig_masks};
use crate::ir::dag::Var;

/// Variables as `motion_lanes` reads them: the unknowns and their sines and cosines from the lane
/// state `st`, the params from the lanes' `self.params[i]`, the rest as the fused body does.
struct LaneVars<'a> {
    cached: &'a Cached<'a>,
    lane: &'a Ident,
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

/// Whether the common path of the mechanism's tick runs in lanes: every block a closed form
/// with a lane kernel (a dyad, RPR, one angle, one length).
fn has_lane_path(c: &Compiled) -> bool {
    !c.blocks.is_empty()
        && c.blocks.iter().all(|b| {
            matches!(
                b.closed_form,
                Some(
                    ClosedForm::Rrr(_)
                        | ClosedForm::Rpr { .. }
                        | ClosedForm::Angle1 { .. }
                        | ClosedForm::Length1 { .. }
                )
            )
        })
}

/// `fn motion_lanes(…)`: positions (the dyads' closed forms), each block's velocities and
/// accelerations from one factorization, then the points, in lanes.
fn motion_lanes(c: &Compiled, args: &Args, vars: &LaneVars) -> TokenStream {
    let (rt, lt) = (&args.rt, vars.lane);
    let m = &c.model;
    let dag = &c.system.dag;
    let (ni, nu, np, npar) = crate::emit::sizes(m);
    let mut b = Builder::new(dag, vars);
    let mut steps = TokenStream::new();
    for bf in &c.blocks {
        let Some(cf) = &bf.closed_form else {
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
                quote!(#rt::lanes::solve_dyad(st, #a, #bb, [#kx, #ky], (#pa, #ra), (#pb, #rb), tolerance, pivot, ok);)
            }
            ClosedForm::Rpr { q, s, .. } => {
                let [kx, ky, mp, mr, np, nr] = [0, 1, 2, 3, 4, 5].map(|i| &r[i]);
                quote!(#rt::lanes::solve_rpr(st, (#q, #s), [#kx, #ky], (#mp, #mr), (#np, #nr), tolerance, pivot, ok);)
            }
            ClosedForm::Angle1 { q, .. } => {
                let (k, p, qq) = (&r[0], opt(1), &r[2]);
                quote!(#rt::lanes::solve_angle1(st, #q, #k, (#p, #qq), tolerance, ok);)
            }
            ClosedForm::Length1 { s, .. } => {
                let (k, a) = (&r[0], &r[1]);
                quote!(#rt::lanes::solve_length1(st, #s, #k, #a, ok);)
            }
            _ => continue,
        };
        steps.extend(quote! {
            #stmts
            #call
        });
    }
    // Near a dead point the scalar refines in double words: such lanes leave the common path.
    steps.extend(quote! {
        *ok = *ok & !pivot.lt(#lt::lit(#rt::REFINE_BELOW));
    });
    for bf in &c.blocks {
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
        let acc = b.segment(&bf.acceleration_rhs);
        let (acc_stmts, acc_rhs) = (&acc.stmts, &acc.roots);
        steps.extend(quote! {
            #stmts
            let mut jac = [[#lt::zero(); #k]; #k];
            #sets
            let lu = #rt::lanes::factor_block(jac, ok);
            let z = lu.solve([#(#rhs),*], ok);
            #( qd[#idx] = z[#zi]; )*
            #acc_stmts
            let z = lu.solve([#(#acc_rhs),*], ok);
            #( qdd[#idx] = z[#zi]; )*
        });
    }
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
    quote! {
        /// The common path of a tick in lanes: every dyad from the last tick's branch, then
        /// velocities, accelerations and points, as `motion_cached` computes them; lanes that
        /// leave it (a dead point, a large turn, a condition below the refinement threshold, a
        /// non-finite value) are cleared in `ok`.
        #[inline(always)]
        fn motion_lanes(&self, fixed: #rt::lanes::LaneFixed<'_, #lt, #ni, #npar>, st: &mut #rt::lanes::LaneTrig<#lt, #nu>,
            tolerance: #lt::Scalar, pivot: &mut #lt, ok: &mut #lt::Mask) -> #rt::lanes::LaneRates<#lt, #nu, #np> {
            let #rt::lanes::LaneFixed { x, xd, xdd, tx, tp } = fixed;
            let mut qd = [#lt::zero(); #nu];
            let mut qdd = [#lt::zero(); #nu];
            #steps
            #stmts
            (qd, qdd, [#(#items),*])
        }
    }
}

/// The lane items of a mechanism's module: `LaneTick<L>`, `Lanes<L>` and its methods.
pub(crate) fn lanes(c: &Compiled, args: &Args) -> TokenStream {
    let (rt, it) = (&args.rt, &args.items);
    let (ty, lt) = (&it.ty, &it.lane_scalar);
    let gt = quote!(#lt::Scalar);
    let (lanes_ty, lane_tick_ty, tick_ty) = (&it.lanes, &it.lane_tick, &it.tick);
    let (ni, nu, np, npar) = crate::emit::sizes(&c.model);
    let (xm, qm, pm) = trig_masks(c);
    let cached = Cached {
        args,
        x: xm.clone(),
        q: qm,
        p: pm,
    };
    let vars = LaneVars {
        cached: &cached,
        lane: lt,
    };
    let fast = has_lane_path(c);
    let motion = fast.then(|| motion_lanes(c, args, &vars));
    let fast_arg = if fast {
        quote! {
            options.closed_forms.then_some(
                |fixed: #rt::lanes::LaneFixed<'_, #lt, #ni, #npar>, st: &mut #rt::lanes::LaneTrig<#lt, #nu>, pivot: &mut #lt, ok: &mut #lt::Mask| {
                    self.motion_lanes(fixed, st, options.newton.tolerance, pivot, ok)
                },
            )
        }
    } else {
        quote! {
            ::core::option::Option::<fn(#rt::lanes::LaneFixed<'_, #lt, #ni, #npar>, &mut #rt::lanes::LaneTrig<#lt, #nu>, &mut #lt, &mut #lt::Mask)
                -> #rt::lanes::LaneRates<#lt, #nu, #np>>::None
        }
    };
    let path_doc = if fast {
        "Its blocks all have lane kernels: the common path of a tick runs in lanes."
    } else {
        "It has blocks without lane kernels (RRP, two lengths, Newton): every lane is ticked by the scalar tick (the same results, no SIMD speed-up)."
    };
    let scalar = quote! {
        |i: usize, t: &mut #tick_ty<#gt>, started: bool, [x, xd, xdd]: [&[#gt; #ni]; 3]| {
            let m = &self.mechanisms.as_ref()[i];
            if started {
                m.tick_arrays(t, x, xd, xdd, options)
            } else {
                let guess = t.q;
                *t = m.tick_start_arrays(x, xd, xdd, &guess, options)?;
                ::core::result::Result::Ok(())
            }
        }
    };
    quote! {
        /// The state of W instances between lane ticks (see `Lanes::tick_start`).
        pub type #lane_tick_ty<#lt> = #rt::LaneTick<#lt, #ni, #nu, #np, #npar>;

        /// W instances of the mechanism in SIMD lanes (`L` = `mechgen::lanes::F64x4` for four f64
        /// instances, `F32x8` for eight f32 ones), each with its own params, inputs and state:
        /// lane `i` of every value is instance `i`, and every lane's result (or error) is the
        /// scalar tick's, to the last bit.
        #[doc = #path_doc]
        #[derive(Clone, Copy, Debug)]
        pub struct #lanes_ty<#lt: #rt::Lanes> {
            mechanisms: #lt::Array<#ty<#lt::Scalar>>,
            params: [#lt; #npar],
            /// Changes with the params (`mechgen::lanes::fresh_params_id`).
            params_id: usize,
        }

        impl<#lt: #rt::Lanes> #lanes_ty<#lt> {
            /// Instance `i` is `f(i)`.
            pub fn from_fn(f: impl FnMut(usize) -> #ty<#lt::Scalar>) -> Self {
                let mechanisms = #lt::array(f);
                let params = ::core::array::from_fn(|k| #lt::from_fn(|i| mechanisms.as_ref()[i].params.to_array()[k]));
                #lanes_ty { mechanisms, params, params_id: #rt::lanes::fresh_params_id() }
            }

            /// Instance `i` (`None` for `i ≥ W`).
            pub fn mechanism(&self, i: usize) -> ::core::option::Option<&#ty<#lt::Scalar>> {
                self.mechanisms.as_ref().get(i)
            }

            /// Sets instance `i` (`BadLength` for `i ≥ W`); its next tick starts its caches afresh.
            pub fn set(&mut self, i: usize, m: #ty<#lt::Scalar>) -> ::core::result::Result<(), #rt::SolveError> {
                let ::core::option::Option::Some(slot) = self.mechanisms.as_mut().get_mut(i) else {
                    return ::core::result::Result::Err(#rt::SolveError::BadLength { expected: #lt::W, got: i });
                };
                *slot = m;
                for (k, v) in m.params.to_array().into_iter().enumerate() {
                    self.params[k].set_lane(i, v);
                }
                self.params_id = #rt::lanes::fresh_params_id();
                ::core::result::Result::Ok(())
            }

            /// The first tick of every instance, each solved from its lane of `guess` by the
            /// scalar `tick_start`. A lane that fails reports its error in `status` and starts
            /// again at the next tick.
            pub fn tick_start(&self, input: &#rt::InputMotion<[#lt; #ni]>, guess: &[#lt; #nu], options: &#rt::SolveOptions<#lt::Scalar>)
                -> #lane_tick_ty<#lt> {
                #rt::lanes::tick_start([&input.x, &input.xd, &input.xdd], guess, #scalar)
            }

            /// One tick of every instance to its lane of `input` (see the scalar `tick`). A lane
            /// that fails reports its error in `status` and keeps its last state; no lane changes
            /// another. No allocation.
            #[inline]
            pub fn tick(&self, t: &mut #lane_tick_ty<#lt>, input: &#rt::InputMotion<[#lt; #ni]>, options: &#rt::SolveOptions<#lt::Scalar>) {
                #rt::lanes::tick(t, (&self.params, self.params_id), [&input.x, &input.xd, &input.xdd], [#(#xm),*], #fast_arg, #scalar)
            }

            #motion
        }

        impl<#lt: #rt::Lanes> #rt::LaneMechanism<#lt> for #lanes_ty<#lt> {
            type Mechanism = #ty<#lt::Scalar>;
            type X = [#lt; #ni];
            type Q = [#lt; #nu];
            type Tick = #lane_tick_ty<#lt>;
            fn from_fn(f: impl FnMut(usize) -> Self::Mechanism) -> Self { #lanes_ty::from_fn(f) }
            fn set(&mut self, i: usize, m: Self::Mechanism) -> ::core::result::Result<(), #rt::SolveError> { #lanes_ty::set(self, i, m) }
            fn tick_start(&self, input: &#rt::InputMotion<Self::X>, guess: &Self::Q, options: &#rt::SolveOptions<#lt::Scalar>) -> Self::Tick {
                #lanes_ty::tick_start(self, input, guess, options)
            }
            #[inline]
            fn tick(&self, t: &mut Self::Tick, input: &#rt::InputMotion<Self::X>, options: &#rt::SolveOptions<#lt::Scalar>) {
                #lanes_ty::tick(self, t, input, options)
            }
            fn lane(t: &Self::Tick, i: usize) -> ::core::option::Option<(::core::result::Result<(), #rt::SolveError>, #tick_ty<#lt::Scalar>)> {
                ::core::option::Option::Some((t.status(i), t.lane(i)?))
            }
        }
    }
}
