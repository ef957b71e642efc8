//! Stage 6e, the lane items: a mechanism's or a scene's `Lanes<L>` (W instances, each with its
//! own params) and `LaneTick<L>`, ticked by the runtime's lane driver (`lanes::tick`) with the
//! lane body of [`crate::emit::lanes`] as its common path where there is one; every other lane
//! (and every lane of a mechanism or scene without one) is ticked by the scalar tick.

use proc_macro2::{Ident, TokenStream};
use quote::{format_ident, quote};

use crate::analysis::Compiled;
use crate::analysis::scene::ScenePlan;
use crate::analysis::structure::BlockId;
use crate::emit::args::Args;
use crate::emit::cache::{Cached, trig_masks};
use crate::emit::lanes::{LaneSubset, LaneVars, has_lane_path, motion_lanes};
use crate::emit::names::ModuleItems;

/// What differs between a mechanism's lane items and a scene's.
struct Spec<'a> {
    args: &'a Args<'a>,
    sub: LaneSubset<'a>,
    /// The params a tick compares (a scene: those it reads).
    read: Vec<bool>,
    /// The unknowns that are angles (with cached sines and cosines) and those a tick predicts
    /// (Newton's), as the scalar tick's `predicted` takes them.
    angle_q: Vec<bool>,
    predict: Vec<bool>,
    /// The lane tick's alias target.
    lane_tick: TokenStream,
    /// The scalar tick of one lane (`lanes::ScalarLane`): its tick state's and memo's types, the
    /// memo's binding and the body (of `i`, `t`, the memo, `started`, `x`, `xd`, `xdd`, `options`).
    scalar_tick: TokenStream,
    memo: (TokenStream, TokenStream),
    scalar: TokenStream,
    /// The instances' field and accessor (`mechanisms`, `mechanism`), and what they are.
    field: Ident,
    accessor: Ident,
    what: &'static str,
}

/// `LaneTick<L>`, `Lanes<L>` and its inherent methods.
fn common(c: &Compiled, s: &Spec) -> TokenStream {
    let (rt, it) = (&s.args.rt, &s.args.items);
    let (ty, lt) = (&it.ty, &it.lane_scalar);
    let (lanes_ty, lane_tick_ty) = (&it.lanes, &it.lane_tick);
    let (ni, nu, _, npar) = crate::emit::args::sizes(&c.model);
    let np = s.sub.points.len();
    let (xm, qm, pm) = trig_masks(c);
    let cached = Cached {
        args: s.args,
        x: xm.clone(),
        q: qm,
        p: pm.clone(),
    };
    let vars = LaneVars {
        cached: &cached,
        lane: lt,
    };
    let fast = has_lane_path(c, s.sub.blocks, s.sub.order);
    let motion = fast.then(|| motion_lanes(c, s.args, &vars, &s.sub));
    let none = quote! {
        ::core::option::Option::<fn(#rt::lanes::LaneFixed<'_, #lt, #ni, #npar>, &mut #rt::lanes::LaneTrig<#lt, #nu>,
            &mut #rt::lanes::LaneReport<#lt>, &mut #lt::Mask)
            -> #rt::lanes::LaneRates<#lt, #nu, #np>>::None
    };
    // The lane path of a tick and of a start (a scene's with values to skip computes them all
    // at its start, as its scalar start does).
    let path = |every: bool| {
        if !fast {
            return none.clone();
        }
        let every = s.sub.values_read.map(|_| quote!(#every));
        quote! {
            options.closed_forms.then_some(
                #[inline(always)]
                |fixed: #rt::lanes::LaneFixed<'_, #lt, #ni, #npar>, st: &mut #rt::lanes::LaneTrig<#lt, #nu>,
                    report: &mut #rt::lanes::LaneReport<#lt>, ok: &mut #lt::Mask| {
                    self.motion_lanes(fixed, st, &options.newton, report, ok, #every)
                },
            )
        }
    };
    let (fast_arg, start_arg) = (path(false), path(true));
    let path_doc = if fast {
        "Its blocks all have lane kernels: the common path of a tick runs in lanes."
    } else {
        "Its tick has no lane path (no blocks, or Newton blocks in a scene below order 2, whose rates come from differences): every lane is ticked by the scalar tick (the same results, no SIMD speed-up)."
    };
    let doc = format!(
        " W instances of the {} in SIMD lanes (`L` = `mechgen::lanes::F64x4` for four f64 \
         instances, `F32x8` for eight f32 ones), each with its own params, inputs and state: lane \
         `i` of every value is instance `i`, and every lane's result (or error) is the scalar \
         tick's, to the last bit.",
        s.what
    );
    let (field, accessor, read) = (&s.field, &s.accessor, &s.read);
    let (scalar_tick, (memo_pat, memo_ty), scalar_body) = (&s.scalar_tick, &s.memo, &s.scalar);
    let scalar = quote! {
        |i: usize, t: &mut #scalar_tick, memo: &mut #memo_ty, started: bool, xs: [&[#lt::Scalar; #ni]; 3]| {
            self.scalar_lane(i, t, memo, started, xs, options)
        }
    };
    let (angle_q, predict) = (&s.angle_q, &s.predict);
    let lane_tick = &s.lane_tick;
    let shape = quote! {
        /// What the lane driver knows of the instances besides their values: the params a tick
        /// compares, the angles among the inputs, unknowns and params, the unknowns it predicts.
        const SHAPE: #rt::lanes::LaneShape<#ni, #nu, #npar> = #rt::lanes::LaneShape { read: [#(#read),*],
            angle_x: [#(#xm),*], angle_q: [#(#angle_q),*], angle_p: [#(#pm),*], predict: [#(#predict),*] };
    };
    let start_doc = if fast {
        "solved from its lane of `guess` in lanes (each lane that leaves the common path by the scalar `tick_start`; the same results)."
    } else {
        "solved from its lane of `guess` by the scalar `tick_start`."
    };
    let start_doc = format!(
        " The first tick of every instance, each {start_doc} A lane that fails reports its error in `status` and starts again at the next tick."
    );
    quote! {
        /// The state of W instances between lane ticks (see `Lanes::tick_start`).
        pub type #lane_tick_ty<#lt> = #lane_tick;

        #[doc = #doc]
        #[doc = ""]
        #[doc = #path_doc]
        #[derive(Clone, Copy, Debug)]
        pub struct #lanes_ty<#lt: #rt::Lanes> {
            #field: #lt::Array<#ty<#lt::Scalar>>,
            params: [#lt; #npar],
            /// Changes with the params (`mechgen::lanes::fresh_params_id`).
            params_id: usize,
        }

        impl<#lt: #rt::Lanes> #lanes_ty<#lt> {
            #shape

            /// Instance `i` is `f(i)`.
            pub fn from_fn(f: impl FnMut(usize) -> #ty<#lt::Scalar>) -> Self {
                let #field = #lt::array(f);
                let params = ::core::array::from_fn(|k| #lt::from_fn(|i| #field.as_ref()[i].params.to_array()[k]));
                #lanes_ty { #field, params, params_id: #rt::lanes::fresh_params_id() }
            }

            /// Instance `i` (`None` for `i ≥ W`).
            pub fn #accessor(&self, i: usize) -> ::core::option::Option<&#ty<#lt::Scalar>> {
                self.#field.as_ref().get(i)
            }

            /// Sets instance `i` (`BadLength` for `i ≥ W`); its next tick starts its caches afresh.
            pub fn set(&mut self, i: usize, m: #ty<#lt::Scalar>) -> ::core::result::Result<(), #rt::SolveError> {
                let ::core::option::Option::Some(slot) = self.#field.as_mut().get_mut(i) else {
                    return ::core::result::Result::Err(#rt::SolveError::BadLength { expected: #lt::W, got: i });
                };
                *slot = m;
                for (k, v) in m.params.to_array().into_iter().enumerate() {
                    self.params[k].set_lane(i, v);
                }
                self.params_id = #rt::lanes::fresh_params_id();
                ::core::result::Result::Ok(())
            }

            #[doc = #start_doc]
            pub fn tick_start(&self, input: &#rt::InputMotion<[#lt; #ni]>, guess: &[#lt; #nu], options: &#rt::SolveOptions<#lt::Scalar>)
                -> #lane_tick_ty<#lt> {
                #rt::lanes::tick_start((&self.params, self.params_id), [&input.x, &input.xd, &input.xdd], guess, &Self::SHAPE,
                    #start_arg, #scalar)
            }

            /// One tick of every instance to its lane of `input` (see the scalar `tick`). A lane
            /// that fails reports its error in `status` and keeps its last state; no lane changes
            /// another. No allocation.
            #[inline(always)]
            pub fn tick(&self, t: &mut #lane_tick_ty<#lt>, input: &#rt::InputMotion<[#lt; #ni]>, options: &#rt::SolveOptions<#lt::Scalar>) {
                #rt::lanes::tick(t, (&self.params, self.params_id), [&input.x, &input.xd, &input.xdd], &Self::SHAPE, #fast_arg, #scalar)
            }

            /// Lane `i` ticked by its scalar tick from `t` (`started`), or started from its guess
            /// `t.q`: what the lane driver runs for a lane off the common path.
            fn scalar_lane(&self, i: usize, t: &mut #scalar_tick, #memo_pat: &mut #memo_ty, started: bool,
                [x, xd, xdd]: [&[#lt::Scalar; #ni]; 3], options: &#rt::SolveOptions<#lt::Scalar>)
                -> ::core::result::Result<(), #rt::SolveError> {
                #scalar_body
            }

            #motion
        }
    }
}

/// The lane items of a mechanism's module: `LaneTick<L>`, `Lanes<L>`, its `LaneMechanism` impl.
pub(crate) fn mechanism(c: &Compiled, args: &Args) -> TokenStream {
    let (rt, it) = (&args.rt, &args.items);
    let lt = &it.lane_scalar;
    let gt = quote!(#lt::Scalar);
    let (ty, lanes_ty, lane_tick_ty, tick_ty) = (&it.ty, &it.lanes, &it.lane_tick, &it.tick);
    let (ni, nu, np, npar) = crate::emit::args::sizes(&c.model);
    let blocks: Vec<BlockId> = c.block_ids().collect();
    let points: Vec<usize> = (0..np).collect();
    let scalar = quote! {
        let m = &self.mechanisms.as_ref()[i];
        if started {
            m.tick_arrays(t, x, xd, xdd, options)
        } else {
            let guess = t.q;
            *t = m.tick_start_arrays(x, xd, xdd, &guess, options)?;
            ::core::result::Result::Ok(())
        }
    };
    let spec = Spec {
        args,
        sub: LaneSubset {
            blocks: &blocks,
            order: 2,
            points: &points,
            values_read: None,
            scale_of: quote!(self.mechanisms.as_ref()[i].params.length_scale()),
        },
        read: vec![true; npar],
        angle_q: trig_masks(c).1,
        predict: crate::emit::closed::closed_mask(c)
            .iter()
            .map(|k| !k)
            .collect(),
        lane_tick: quote!(#rt::LaneTick<#lt, #ni, #nu, #np, #npar>),
        scalar_tick: quote!(#tick_ty<#gt>),
        memo: (quote!(_memo), quote!(())),
        scalar,
        field: format_ident!("mechanisms"),
        accessor: format_ident!("mechanism"),
        what: "mechanism",
    };
    let items = common(c, &spec);
    quote! {
        #items

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
            #[inline(always)]
            fn tick(&self, t: &mut Self::Tick, input: &#rt::InputMotion<Self::X>, options: &#rt::SolveOptions<#lt::Scalar>) {
                #lanes_ty::tick(self, t, input, options)
            }
            fn lane(t: &Self::Tick, i: usize) -> ::core::option::Option<(::core::result::Result<(), #rt::SolveError>, #tick_ty<#lt::Scalar>)> {
                ::core::option::Option::Some((t.status(i), t.lane(i)?))
            }
        }
    }
}

/// The lane items of a scene's module: `LaneTick<L>` (its mechanism's tick for the kept blocks
/// and the scene's points, with each lane's `SceneMemo`), `Lanes<L>` with `outputs`, and its
/// `LaneScene` impl. Its lane body is its scalar tick's subset (`every_angle` false in a tick,
/// true in a start, as its scalar body).
pub(crate) fn scene(c: &Compiled, plan: &ScenePlan, rt: &TokenStream, ncols: usize) -> TokenStream {
    let args = Args {
        model: &c.model,
        rt: rt.clone(),
        items: ModuleItems::new(&plan.name),
    };
    let it = &args.items;
    let lt = &it.lane_scalar;
    let gt = quote!(#lt::Scalar);
    let (ty, lanes_ty, lane_tick_ty, outputs_ty) = (&it.ty, &it.lanes, &it.lane_tick, &it.outputs);
    let (ni, nu, _, npar) = crate::emit::args::sizes(&c.model);
    let np = plan.points.len();
    let (tick_fn, start_fn, scale_fn) = (
        format_ident!("scene_{}_tick", plan.name),
        format_ident!("scene_{}_tick_start", plan.name),
        format_ident!("scene_{}_length_scale", plan.name),
    );
    let q_trig = trig_masks(c).1;
    let closed = crate::emit::closed::closed_mask(c);
    let scalar = quote! {
        let m = self.scenes.as_ref()[i].mechanism();
        // On error too: what the scalar tick leaves in its state.
        let (s, r) = if started {
            let mut s = #rt::scene_tick_join(*t, *memo);
            let r = m.#tick_fn(&mut s, x, xd, xdd, options);
            (s, r)
        } else {
            (m.#start_fn(x, xd, xdd, &t.q, options)?, ::core::result::Result::Ok(()))
        };
        (*t, *memo) = #rt::scene_tick_parts(s);
        r
    };
    let spec = Spec {
        args: &args,
        sub: LaneSubset {
            blocks: &plan.blocks,
            order: plan.order.as_number(),
            points: &plan.points,
            // As the scalar body: only a subset with an angle to skip reads the flags.
            values_read: (!plan.angles_skipped.is_empty()).then_some(&plan.values_read[..]),
            scale_of: quote!(self.scenes.as_ref()[i].mechanism().#scale_fn()),
        },
        read: plan.params_read.clone(),
        angle_q: (0..nu)
            .map(|k| q_trig[k] && plan.solved.contains(&k))
            .collect(),
        predict: (0..nu)
            .map(|k| !closed[k] && plan.solved.contains(&k))
            .collect(),
        lane_tick: quote!(#rt::LaneTick<#lt, #ni, #nu, #np, #npar, #rt::SceneMemo<<#lt as #rt::Lanes>::Scalar>>),
        scalar_tick: quote!(#rt::Tick<#gt, #ni, #nu, #np, #npar>),
        memo: (quote!(memo), quote!(#rt::SceneMemo<#gt>)),
        scalar,
        field: format_ident!("scenes"),
        accessor: format_ident!("scene"),
        what: "scene",
    };
    let items = common(c, &spec);
    quote! {
        #items

        impl<#lt: #rt::Lanes> #lanes_ty<#lt> {
            /// The outputs of every lane (lane `i` of each field is instance `i`'s; a lane that
            /// never started holds zeros).
            pub fn outputs(t: &#lane_tick_ty<#lt>) -> #outputs_ty<#lt> {
                columns_of(&t.q, &t.qd, &t.qdd, &t.points)
            }
        }

        impl<#lt: #rt::Lanes> #rt::LaneScene<#lt> for #lanes_ty<#lt> {
            type Scene = #ty<#lt::Scalar>;
            type X = [#lt; #ni];
            type Q = [#lt; #nu];
            type Out = [#lt; #ncols];
            type Tick = #lane_tick_ty<#lt>;
            fn from_fn(f: impl FnMut(usize) -> Self::Scene) -> Self { #lanes_ty::from_fn(f) }
            fn set(&mut self, i: usize, s: Self::Scene) -> ::core::result::Result<(), #rt::SolveError> { #lanes_ty::set(self, i, s) }
            fn tick_start(&self, input: &#rt::InputMotion<Self::X>, guess: &Self::Q, options: &#rt::SolveOptions<#lt::Scalar>) -> Self::Tick {
                #lanes_ty::tick_start(self, input, guess, options)
            }
            #[inline(always)]
            fn tick(&self, t: &mut Self::Tick, input: &#rt::InputMotion<Self::X>, options: &#rt::SolveOptions<#lt::Scalar>) {
                #lanes_ty::tick(self, t, input, options)
            }
            fn outputs(t: &Self::Tick) -> Self::Out { #lanes_ty::outputs(t).to_array() }
            fn lane(t: &Self::Tick, i: usize)
                -> ::core::option::Option<(::core::result::Result<(), #rt::SolveError>, #rt::SceneTick<#lt::Scalar, #ni, #nu, #np, #npar>)> {
                ::core::option::Option::Some((t.status(i), #rt::scene_tick_join(t.lane(i)?, t.memo(i)?)))
            }
        }
    }
}
