//! Stage 6d: scenes. Each scene's pruned solver is a fused body ([`crate::emit::motion::Subset`]:
//! its kept blocks, its order, its points) with `solve`/`tick_start`/`tick` around it, emitted as
//! hidden methods of its mechanism's type (they call the block functions), and a module `NAME`
//! with the scene's type, `Params`/`Inputs`/`Unknowns` re-exported from the mechanism, `Outputs`
//! (only the scene's fields), the `Tick` alias and the `mechgen::Scene` impl.

use proc_macro2::{Ident, TokenStream};
use quote::{format_ident, quote};

use crate::analysis::Compiled;
use crate::analysis::scene::ScenePlan;
use crate::emit::args::Args;
use crate::emit::body::VarSource;
use crate::emit::comments::comment;
use crate::emit::motion::{Subset, motion_subset};
use crate::emit::names::{ModuleItems, Names};

fn method(plan: &ScenePlan, what: &str) -> Ident {
    format_ident!("scene_{}_{}", plan.name, what)
}

/// Masks over the unknowns: angles the scene's kept blocks solve (their sines and cosines are
/// cached), and unknowns a tick does not predict (closed forms, and everything outside the kept
/// blocks, which is carried unchanged).
fn masks(c: &Compiled, plan: &ScenePlan) -> (Vec<bool>, Vec<bool>, Vec<bool>) {
    let nu = c.model.unknowns.len();
    let (_, q_trig, _) = crate::emit::cache::trig_masks(c);
    let solved = plan.solved.clone();
    let angle: Vec<bool> = (0..nu).map(|k| q_trig[k] && solved.contains(&k)).collect();
    let closed = crate::emit::closed::closed_mask(c);
    let keep_closed: Vec<bool> = (0..nu).map(|k| closed[k] || !solved.contains(&k)).collect();
    let keep_newton: Vec<bool> = (0..nu).map(|k| !solved.contains(&k)).collect();
    (angle, keep_closed, keep_newton)
}

/// The hidden methods of every scene of `c`, inside the mechanism's `impl`.
pub(crate) fn methods(c: &Compiled, cached: &dyn VarSource, args: &Args) -> TokenStream {
    let (rt, gt) = (&args.rt, &args.items.scalar);
    let (ni, nu, _, npar) = crate::emit::args::sizes(&c.model);
    let (x_trig, _, _) = crate::emit::cache::trig_masks(c);
    let mut out = TokenStream::new();
    for plan in &c.scenes {
        let np = plan.points.len();
        let motion_fn = method(plan, "motion");
        let values_read = plan.values_read.clone();
        let read = plan.params_read.clone();
        // The scene's length scale: the largest length param it reads (its results depend on no
        // other param, not even through Newton's tolerance).
        let scale_fn = method(plan, "length_scale");
        let read_lengths: Vec<TokenStream> = (c.model.params.iter().zip(&read))
            .filter(|(p, r)| **r && p.kind == crate::sema::model::Kind::Length)
            .map(|(p, _)| {
                let p = format_ident!("{}", p.name.text);
                quote!(self.params.#p)
            })
            .collect();
        let scale_body = crate::emit::args::largest_length(gt, &read_lengths);
        let angles_skipped = plan.angles_skipped.clone();
        let skipped: Vec<bool> = (0..c.model.unknowns.len())
            .map(|k| angles_skipped.contains(&k))
            .collect();
        let sub = Subset {
            blocks: &plan.blocks,
            order: plan.order.as_number(),
            points: &plan.points,
            name: motion_fn.clone(),
            vis: quote!(#[doc(hidden)] pub(super)),
            // Only a body with an angle to skip takes `every_angle`.
            values_read: skipped.iter().any(|&k| k).then_some(&values_read[..]),
            length_scale: quote!(self.#scale_fn()),
            bodies: false,
        };
        let every = |value: bool| sub.values_read.map(|_| quote!(, #value));
        let (every_true, every_false) = (every(true), every(false));
        let body = motion_subset(c, cached, rt, &sub);
        let (angle, keep_closed, keep_newton) = masks(c, plan);

        // Every kept block in closed form: with closed forms on, the guess is the last tick's
        // state as it is (nothing to predict, no sines or cosines to rotate).
        // Closed forms off: angles a tick left stale are made whole before Newton predicts.
        let whole = skipped.iter().any(|&k| k).then(|| {
            let names: Vec<&str> = angles_skipped
                .iter()
                .map(|&k| c.model.unknowns[k].name.text.as_str())
                .collect();
            let note = comment(&format!(
                "Angles this tick does not compute (read through their sine and cosine only): {}.",
                names.join(", ")
            ));
            quote!(#note if !options.closed_forms { t.principal_angles([#(#skipped),*]); })
        });
        let read_names: Vec<&str> = (c.model.params.iter().zip(&read))
            .filter(|(_, r)| **r)
            .map(|(p, _)| p.name.text.as_str())
            .collect();
        let params_comment = comment(&format!(
            "The params the scene reads, the only ones compared and checked: {}.",
            if read_names.is_empty() {
                "none".to_string()
            } else {
                read_names.join(", ")
            }
        ));
        // Below order 2 with Newton blocks: the rates the scene does not compute, estimated by
        // differences for its predictor (skipped angles are stale: not theirs).
        let order = plan.order.as_number();
        let solved = plan.solved.clone();
        let estimate: Vec<bool> = (0..c.model.unknowns.len())
            .map(|k| solved.contains(&k) && !skipped[k])
            .collect();
        let estimated = (order < 2 && keep_closed.iter().any(|&k| !k)).then(|| {
            quote! {
                let (qd, qdd) = #rt::scene_rates_estimated(tick, x, xd, &st.q, qd, #order, [#(#estimate),*], same);
                let t = #rt::scene_tick_state_mut(tick);
            }
        });
        // The motion's q̈ is replaced by the estimate: not bound.
        let qdd_pat = if estimated.is_some() {
            quote!(_)
        } else {
            quote!(qdd)
        };
        let guess = if keep_closed.iter().all(|&k| k) {
            quote! {
                if options.closed_forms { t.carried([#(#angle),*]) }
                else { t.predicted(x, [#(#angle),*], [#(#keep_newton),*], same) }
            }
        } else {
            quote! {
                if options.closed_forms { t.predicted(x, [#(#angle),*], [#(#keep_closed),*], same) }
                else { t.predicted(x, [#(#angle),*], [#(#keep_newton),*], same) }
            }
        };
        let (solve_fn, start_fn, tick_fn) = (
            method(plan, "solve"),
            method(plan, "tick_start"),
            method(plan, "tick"),
        );
        let doc = format!(" Scene `{}`: its pruned solver.", plan.name);
        out.extend(comment(&format!(
            "Scene {}: blocks {:?}, order {}, points {:?}.",
            plan.name,
            plan.block_indices(),
            plan.order.as_number(),
            plan.points
        )));
        out.extend(quote! {
            /// The largest length param the scene reads (1 when there is none).
            #[doc(hidden)]
            #[inline]
            pub(super) fn #scale_fn(&self) -> #gt {
                #scale_body
            }

            #body

            #[doc = #doc]
            #[doc(hidden)]
            #[inline]
            pub(super) fn #solve_fn(&self, x: &[#gt; #ni], xd: &[#gt; #ni], xdd: &[#gt; #ni], q: &mut [#gt; #nu],
                options: &#rt::SolveOptions<#gt>)
                -> ::core::result::Result<#rt::RatesReport<#gt, #nu, #np>, #rt::SolveError> {
                #rt::check_finite_in(#rt::Quantity::Param, &self.params.to_array(), [#(#read),*])?;
                #rt::check_finite(#rt::Quantity::Input, x)?;
                #rt::check_finite(#rt::Quantity::Guess, q)?;
                #rt::check_finite(#rt::Quantity::InputRate, xd)?;
                #rt::check_finite(#rt::Quantity::InputAcceleration, xdd)?;
                let (tx, tp) = self.trig_fixed(x);
                let mut st = #rt::TrigState::new(*q, [#(#angle),*]);
                let mut report = #rt::NewtonReport::new();
                let fixed = #rt::Fixed { x, xd, xdd, tx: &tx, tp: &tp };
                let (qd, qdd, points) = self.#motion_fn(fixed, &mut st, options, &mut report #every_true)?;
                *q = st.q;
                Ok((qd, qdd, points, report))
            }

            #[doc(hidden)]
            pub(super) fn #start_fn(&self, x: &[#gt; #ni], xd: &[#gt; #ni], xdd: &[#gt; #ni], guess: &[#gt; #nu],
                options: &#rt::SolveOptions<#gt>) -> ::core::result::Result<#rt::SceneTick<#gt, #ni, #nu, #np, #npar>, #rt::SolveError> {
                use #rt::TickCache as _;
                let mut q = *guess;
                let (qd, qdd, points, report) = self.#solve_fn(x, xd, xdd, &mut q, options)?;
                let (tx, tp) = self.trig_fixed(x);
                let st = #rt::TrigState::new(q, [#(#angle),*]);
                Ok(#rt::scene_tick(#rt::Tick::new(#rt::Solution { x: *x, xd: *xd, xdd: *xdd, q, qd, qdd, points, report,
                    tx, tq: st.sc, tp, params: self.params.to_array() })))
            }

            #[doc(hidden)]
            #[inline]
            pub(super) fn #tick_fn(&self, tick: &mut #rt::SceneTick<#gt, #ni, #nu, #np, #npar>, x: &[#gt; #ni], xd: &[#gt; #ni],
                xdd: &[#gt; #ni], options: &#rt::SolveOptions<#gt>) -> ::core::result::Result<(), #rt::SolveError> {
                use #rt::TickCache as _;
                let t = #rt::scene_tick_state_mut(tick);
                let params = self.params.to_array();
                #params_comment
                let same = t.same_params_in(&params, [#(#read),*]);
                if !same {
                    #rt::check_finite_in(#rt::Quantity::Param, &params, [#(#read),*])?;
                }
                #rt::check_finite(#rt::Quantity::Input, x)?;
                #rt::check_finite(#rt::Quantity::InputRate, xd)?;
                #rt::check_finite(#rt::Quantity::InputAcceleration, xdd)?;
                #whole
                let mut fresh_tp = None;
                let (tx, tp) = if same {
                    (t.inputs_trig(x, [#(#x_trig),*]), t.params_trig())
                } else {
                    let (tx, tp) = self.trig_fixed(x);
                    (tx, &*fresh_tp.insert(tp))
                };
                let mut st = #guess;
                let mut report = #rt::NewtonReport::new();
                let fixed = #rt::Fixed { x, xd, xdd, tx: &tx, tp };
                let (qd, #qdd_pat, points) = self.#motion_fn(fixed, &mut st, options, &mut report #every_false)?;
                #estimated
                t.update(x, xd, xdd, &st, qd, qdd, points, report, tx, fresh_tp.as_ref().map(|tp| (&params, tp)));
                Ok(())
            }
        });
    }
    out
}

/// An output column and the expression that reads it from `q`, `qd`, `qdd`, `points`.
struct Column {
    name: String,
    read: TokenStream,
}

/// The output columns of interfaces.md, unknowns first, then points, each up to the order.
fn columns(c: &Compiled, plan: &ScenePlan) -> Vec<Column> {
    let order = plan.order.as_number();
    let mut cols = Vec::new();
    for &u in &plan.unknowns {
        let n = &c.model.unknowns[u].name.text;
        let arrays = [quote!(q), quote!(qd), quote!(qdd)];
        for (o, (suffix, arr)) in ["", "_vel", "_acc"].iter().zip(arrays).enumerate() {
            if o <= usize::from(order) {
                cols.push(Column {
                    name: format!("{n}{suffix}"),
                    read: quote!(#arr[#u]),
                });
            }
        }
    }
    for (i, &p) in plan.points.iter().enumerate() {
        let n = &c.model.points[p].0.text;
        let fields = [quote!(position), quote!(velocity), quote!(acceleration)];
        for (o, (s, f)) in [("x", "y"), ("vx", "vy"), ("ax", "ay")]
            .iter()
            .zip(fields)
            .enumerate()
        {
            if o <= usize::from(order) {
                cols.push(Column {
                    name: format!("{n}_{}", s.0),
                    read: quote!(points[#i].#f[0]),
                });
                cols.push(Column {
                    name: format!("{n}_{}", s.1),
                    read: quote!(points[#i].#f[1]),
                });
            }
        }
    }
    cols
}

/// The module of one scene (a sibling of its mechanism's module).
pub(crate) fn module(c: &Compiled, plan: &ScenePlan, rt: &TokenStream) -> TokenStream {
    let m = &c.model;
    let mech = ModuleItems::new(&m.name.text);
    let it = ModuleItems::new(&plan.name);
    let (ty, gt, outputs_ty, tick_ty) = (&it.ty, &it.scalar, &it.outputs, &it.tick);
    let (params_ty, inputs_ty, unknowns_ty) = (&it.params, &it.inputs, &it.unknowns);
    let (m_params, m_inputs, m_unknowns, m_ty) =
        (&mech.params, &mech.inputs, &mech.unknowns, &mech.ty);
    let mech_mod = format_ident!("{}", m.name.text);
    let mod_name = format_ident!("{}", plan.name);
    let (ni, nu, _, npar) = crate::emit::args::sizes(m);
    let np = plan.points.len();
    let cols = columns(c, plan);
    let ncols = cols.len();
    let col_names: Vec<&str> = cols.iter().map(|c| c.name.as_str()).collect();
    let reads = cols.iter().map(|c| &c.read);
    let lanes = crate::emit::lane_items::scene(c, plan, rt, ncols);
    let (lanes_ty, lt) = (&it.lanes, &it.lane_scalar);
    let mut fields: Names<usize> = Names::new(["_scalar"]);
    let field_ids: Vec<Ident> = cols
        .iter()
        .enumerate()
        .map(|(i, c)| fields.get(i, &[&c.name]))
        .collect();
    let col_idx = 0..ncols;
    let (name, mech_name) = (&plan.name, &m.name.text);
    let order = proc_macro2::Literal::u8_unsuffixed(plan.order.as_number());
    let blocks = &plan.blocks;
    let solved = plan.solved.clone();
    let skipped = plan.angles_skipped.clone();
    let unknown_names = plan.unknowns.iter().map(|&u| &m.unknowns[u].name.text);
    let point_names = plan.points.iter().map(|&p| &m.points[p].0.text);
    let doc = format!(
        "Scene `{name}` of mechanism `{mech_name}`: {} to order {order}; solves blocks `{:?}` only.",
        col_names.join(", "),
        plan.block_indices()
    );
    let marker =
        (ncols == 0).then(|| quote!(#[doc(hidden)] pub _scalar: ::core::marker::PhantomData<#gt>,));
    let marker_init = (ncols == 0).then(|| quote!(_scalar: ::core::marker::PhantomData,));
    let (solve_fn, start_fn, tick_fn) = (
        method(plan, "solve"),
        method(plan, "tick_start"),
        method(plan, "tick"),
    );
    // Why each allow of the module's `#![allow]` is there, as `//` lines below it.
    let allow_reasons: TokenStream = [
        "Allowed above, and why:",
        "non_snake_case: output fields keep the file's names (`P_x`, `u_vel`).",
    ]
    .iter()
    .map(|t| comment(t))
    .collect();
    quote! {
        #[doc = #doc]
        pub mod #mod_name {
            #![allow(non_snake_case)]
            #allow_reasons

            pub use super::#mech_mod::{#m_params as #params_ty, #m_inputs as #inputs_ty, #m_unknowns as #unknowns_ty};

            /// What the scene keeps of its mechanism, and its output columns.
            pub const INFO: #rt::SceneInfo = #rt::SceneInfo {
                name: #name,
                mechanism: #mech_name,
                order: #order,
                blocks: &[#(#blocks),*],
                solved: &[#(#solved),*],
                angles_skipped: &[#(#skipped),*],
                unknowns: &[#(#unknown_names),*],
                points: &[#(#point_names),*],
                columns: &[#(#col_names),*],
            };

            /// The scene's outputs, one field per column of `INFO.columns` (a point's
            /// coordinates as `P_x`, `P_y`, rates as `u_vel`, `P_vx`, …).
            #[derive(Clone, Copy, Debug, Default, PartialEq)]
            pub struct #outputs_ty<#gt> { #( pub #field_ids: #gt, )* #marker }

            /// What `solve` returns (`mechgen::SceneState`): the inputs with their rates, the
            /// unknowns (the kept blocks' solved), the outputs and the Newton report.
            pub type Solved<#gt> = #rt::SceneState<#inputs_ty<#gt>, #unknowns_ty<#gt>, #outputs_ty<#gt>, #gt>;
            impl<#gt: ::core::marker::Copy> #outputs_ty<#gt> {
                pub fn from_array(a: [#gt; #ncols]) -> Self { #outputs_ty { #( #field_ids: a[#col_idx], )* #marker_init } }
                pub fn to_array(&self) -> [#gt; #ncols] { [#(self.#field_ids),*] }
            }

            /// The output columns read from a solved state, of one instance or of W in lanes.
            #[inline]
            fn columns_of<V: ::core::marker::Copy>(q: &[V; #nu], qd: &[V; #nu], qdd: &[V; #nu], points: &[#rt::PointMotion<V>; #np])
                -> #outputs_ty<V> {
                #outputs_ty::from_array([#(#reads),*])
            }

            #lanes

            /// The state between ticks (read it with `outputs`): the kept blocks' unknowns with
            /// their rates up to the scene's order, the scene's points, and the caches.
            pub type #tick_ty<#gt> = #rt::SceneTick<#gt, #ni, #nu, #np, #npar>;

            #[doc = #doc]
            #[derive(Clone, Copy, Debug, PartialEq)]
            pub struct #ty<#gt = f64> { pub params: #params_ty<#gt> }
            impl<#gt: #rt::Real> ::core::default::Default for #ty<#gt> {
                fn default() -> Self { #ty { params: <#params_ty<#gt> as ::core::default::Default>::default() } }
            }

            impl<#gt: #rt::Real> #ty<#gt> {
                pub fn new(params: #params_ty<#gt>) -> Self { #ty { params } }

                #[inline(always)]
                fn mechanism(&self) -> super::#mech_mod::#m_ty<#gt> { super::#mech_mod::#m_ty::new(self.params) }

                /// The mechanism's `start` configuration.
                pub fn start() -> (#inputs_ty<#gt>, #unknowns_ty<#gt>) { super::#mech_mod::#m_ty::<#gt>::start() }

                #[inline]
                fn outputs_of(q: &[#gt; #nu], qd: &[#gt; #nu], qdd: &[#gt; #nu], points: &[#rt::PointMotion<#gt>; #np]) -> #outputs_ty<#gt> {
                    columns_of(q, qd, qdd, points)
                }

                /// Positions of the kept blocks from `guess`, their rates up to the order, the
                /// outputs; the returned unknowns hold the kept blocks' solution.
                pub fn solve(&self, input: &#rt::InputMotion<#inputs_ty<#gt>>, guess: &#unknowns_ty<#gt>,
                    options: &#rt::SolveOptions<#gt>)
                    -> ::core::result::Result<Solved<#gt>, #rt::SolveError> {
                    let mut q = guess.to_array();
                    let (qd, qdd, points, report) = self.mechanism().#solve_fn(&input.x.to_array(), &input.xd.to_array(),
                        &input.xdd.to_array(), &mut q, options)?;
                    Ok(Solved { x: input.x, xd: input.xd, xdd: input.xdd, q: #unknowns_ty::from_array(q),
                        out: Self::outputs_of(&q, &qd, &qdd, &points), report })
                }

                /// [`Self::solve`] into `state`: its inputs and rates are the input, its unknowns
                /// the guess; on success it holds the solution, on error it is unchanged.
                pub fn solve_in_place(&self, state: &mut Solved<#gt>, options: &#rt::SolveOptions<#gt>)
                    -> ::core::result::Result<(), #rt::SolveError> {
                    *state = self.solve(&state.input(), &state.q, options)?;
                    Ok(())
                }

                /// The first tick of a simulation, solved from `guess` (see `tick`).
                pub fn tick_start(&self, input: &#rt::InputMotion<#inputs_ty<#gt>>, guess: &#unknowns_ty<#gt>,
                    options: &#rt::SolveOptions<#gt>) -> ::core::result::Result<#tick_ty<#gt>, #rt::SolveError> {
                    self.mechanism().#start_fn(&input.x.to_array(), &input.xd.to_array(), &input.xdd.to_array(),
                        &guess.to_array(), options)
                }

                /// One simulator tick to `input`: the mechanism's tick (predictor, cached sines
                /// and cosines, closed forms on the last branch) on the kept blocks only. On
                /// error `t` reads as before (its outputs, inputs and report are unchanged).
                #[inline]
                pub fn tick(&self, t: &mut #tick_ty<#gt>, input: &#rt::InputMotion<#inputs_ty<#gt>>,
                    options: &#rt::SolveOptions<#gt>) -> ::core::result::Result<(), #rt::SolveError> {
                    self.mechanism().#tick_fn(t, &input.x.to_array(), &input.xd.to_array(), &input.xdd.to_array(), options)
                }

                /// The outputs of a tick state.
                pub fn outputs(t: &#tick_ty<#gt>) -> #outputs_ty<#gt> {
                    let s = #rt::scene_tick_state(t);
                    Self::outputs_of(&s.q, &s.qd, &s.qdd, &s.points)
                }
            }

            impl<#gt: #rt::Real> #rt::Scene<#gt> for #ty<#gt> {
                const NAME: &'static str = #name;
                type X = [#gt; #ni];
                type Q = [#gt; #nu];
                type Out = [#gt; #ncols];
                type Tick = #tick_ty<#gt>;
                type Lanes<#lt: #rt::Lanes<Scalar = #gt>> = #lanes_ty<#lt>;
                fn info(&self) -> &'static #rt::SceneInfo { &INFO }
                fn with_params(params: &[#gt]) -> ::core::option::Option<Self> {
                    <[#gt; #npar]>::try_from(params).ok().map(|a| #ty::new(#params_ty::from_array(a)))
                }
                fn solve(&self, input: &#rt::InputMotion<Self::X>, guess: &Self::Q, options: &#rt::SolveOptions<#gt>)
                    -> ::core::result::Result<#rt::SceneStateOf<Self, #gt>, #rt::SolveError> {
                    let mut q = *guess;
                    let (qd, qdd, points, report) = self.mechanism().#solve_fn(&input.x, &input.xd, &input.xdd, &mut q, options)?;
                    let out = Self::outputs_of(&q, &qd, &qdd, &points).to_array();
                    Ok(#rt::SceneState { x: input.x, xd: input.xd, xdd: input.xdd, q, out, report })
                }
                fn tick_start(&self, input: &#rt::InputMotion<Self::X>, guess: &Self::Q, options: &#rt::SolveOptions<#gt>)
                    -> ::core::result::Result<Self::Tick, #rt::SolveError> {
                    self.mechanism().#start_fn(&input.x, &input.xd, &input.xdd, guess, options)
                }
                fn tick(&self, t: &mut Self::Tick, input: &#rt::InputMotion<Self::X>, options: &#rt::SolveOptions<#gt>)
                    -> ::core::result::Result<(), #rt::SolveError> {
                    self.mechanism().#tick_fn(t, &input.x, &input.xd, &input.xdd, options)
                }
                fn outputs(&self, t: &Self::Tick) -> Self::Out { #ty::outputs(t).to_array() }
                fn report(&self, t: &Self::Tick) -> #rt::NewtonReport<#gt> { *t.report() }
            }
        }
    }
}

/// Every scene of the file, mechanism by mechanism in file order.
pub(crate) fn all(mechs: &[Compiled]) -> Vec<(&Compiled, ScenePlan)> {
    mechs
        .iter()
        .flat_map(|c| c.scenes.iter().map(move |s| (c, s.clone())))
        .collect()
}
