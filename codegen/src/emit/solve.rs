//! Stage 6b: the solver methods of one mechanism: Newton's residual-and-Jacobian function per
//! block, the sine and cosine caches (`tx`, `tp`, and the `TrigState`'s `sc`, computed once per
//! solve and kept in step through Newton by rotation), and the public entry points (positions,
//! velocities, accelerations, the full state, ticks), which run the steps of the fused body
//! (`emit_motion`): each quantity is written once per function that needs it.

use proc_macro2::TokenStream;
use quote::{format_ident, quote};

use crate::analysis::Compiled;
use crate::emit::args::Args;
use crate::emit::body::body;
use crate::emit::cache::{Cached, trig_masks};
use crate::emit::motion::jacobian_sets;

/// The solver methods of a mechanism's type (inside its `impl<T: Real>` block).
pub(crate) fn solvers(c: &Compiled, args: &Args) -> TokenStream {
    let (rt, gt, tick_ty) = (&args.rt, &args.items.scalar, &args.items.tick);
    let m = &c.model;
    let dag = &c.system.dag;
    let (ni, nu, np, npar) = crate::emit::args::sizes(m);
    let (xm, qm, pm) = trig_masks(c);
    let cached = Cached {
        args,
        x: xm.clone(),
        q: qm.clone(),
        p: pm.clone(),
    };
    let trig_sets = |mask: &[bool], arr: TokenStream, src: TokenStream| -> TokenStream {
        let idx: Vec<usize> = (0..mask.len()).filter(|&i| mask[i]).collect();
        quote!(#( #arr[#idx] = #src[#idx].sin_cos(); )*)
    };
    let tx_sets = trig_sets(&xm, quote!(tx), quote!(x));
    let tp_sets = trig_sets(&pm, quote!(tp), quote!(params));
    // Bindings only where something is written into them (no unused `mut`, no unused `params`).
    let tx_mut = xm.iter().any(|&a| a).then(|| quote!(mut));
    let tp_mut = pm.iter().any(|&a| a).then(|| quote!(mut));
    let params_let = tp_mut
        .as_ref()
        .map(|_| quote!(let params = self.params.to_array();));
    // `[]` for an empty array (a repeat expression of length 0 would evaluate its operand).
    let unit_trig = |n: usize| match n {
        0 => quote!([]),
        _ => quote!([(#gt::zero(), #gt::one()); #n]),
    };
    let (tx_init, tp_init) = (unit_trig(ni), unit_trig(npar));
    let ctx = quote!(tx: &[(#gt, #gt); #ni], tp: &[(#gt, #gt); #npar], tq: &[(#gt, #gt); #nu]);

    // Newton's residual and Jacobian of each block (every block: with `closed_forms` off, the
    // closed-form ones run Newton too). Everything else is in the fused body and its stages.
    let mut block_fns = TokenStream::new();
    for (bi, bf) in c.blocks.iter().enumerate() {
        let k = bf.block.unknowns.len();
        let members: Vec<&str> = bf
            .block
            .unknowns
            .iter()
            .map(|&u| m.unknowns[u.index()].name.text.as_str())
            .collect();
        let header = format!(
            "Block {bi}: {} from {}.",
            members.join(", "),
            crate::emit::args::equations_text(&bf.block.equations)
        );
        let mut roots = bf.residual.clone();
        roots.extend(bf.jacobian.iter().flatten());
        let b = body(dag, &roots, &cached);
        let (stmts, v, sets) = (&b.stmts, &b.roots[..k], jacobian_sets(c, bi, &b.roots[k..]));
        let fname = format_ident!("block{}_position", bi);
        let doc = format!(" {header} Its residual and Jacobian block (Newton).");
        block_fns.extend(quote! {
            #[doc = #doc]
            #[inline]
            fn #fname(&self, x: &[#gt; #ni], q: &[#gt; #nu], #ctx) -> (#rt::nalgebra::SVector<#gt, #k>, #rt::nalgebra::SMatrix<#gt, #k, #k>) {
                #stmts
                let mut jac = #rt::nalgebra::SMatrix::<#gt, #k, #k>::zeros();
                #sets
                (#rt::nalgebra::SVector::from([#(#v),*]), jac)
            }
        });
    }

    block_fns.extend(crate::emit::twofold::residual_fns(c, args));
    let motion = crate::emit::motion::motion(c, &cached, rt);
    let stages = crate::emit::motion::stages(c, &cached, rt);
    let scene_methods = crate::emit::scene::methods(c, &cached, args);
    let angle_mask = &qm;
    let closed_mask = crate::emit::closed::closed_mask(c);
    let input_mask = &xm;
    // Every block in closed form: with closed forms on, the guess is the last tick's state as it
    // is (nothing to predict, no sines or cosines to rotate).
    let guess = if closed_mask.iter().all(|&k| k) {
        quote! {
            if options.closed_forms { t.carried([#(#angle_mask),*]) }
            else { t.predicted(x, [#(#angle_mask),*], [false; #nu], same) }
        }
    } else {
        quote! {
            if options.closed_forms { t.predicted(x, [#(#angle_mask),*], [#(#closed_mask),*], same) }
            else { t.predicted(x, [#(#angle_mask),*], [false; #nu], same) }
        }
    };

    // One tick (`tick_arrays`) and, for a mechanism with bodies, one that also computes their mass
    // properties and motion in the same body (`tick_dynamics_arrays`): one template.
    let tick_fn = |name: &str,
                   motion: &str,
                   (generics, extra): (TokenStream, TokenStream),
                   extra_names: TokenStream,
                   attrs: TokenStream| {
        let (name, motion) = (format_ident!("{name}"), format_ident!("{motion}"));
        quote! {
            #attrs
            fn #name #generics(&self, t: &mut #tick_ty<#gt>, x: &[#gt; #ni], xd: &[#gt; #ni], xdd: &[#gt; #ni],
                options: &#rt::SolveOptions<#gt>, #extra) -> ::core::result::Result<(), #rt::SolveError> {
                use #rt::TickCache as _;
                let params = self.params.to_array();
                let same = t.same_params(&params);
                if !same {
                    #rt::check_finite(#rt::Quantity::Param, &params)?;
                }
                #rt::check_finite(#rt::Quantity::Input, x)?;
                #rt::check_finite(#rt::Quantity::InputRate, xd)?;
                #rt::check_finite(#rt::Quantity::InputAcceleration, xdd)?;
                let mut fresh_tp = None;
                let (tx, tp) = if same {
                    (t.inputs_trig(x, [#(#input_mask),*]), t.params_trig())
                } else {
                    let (tx, tp) = self.trig_fixed(x);
                    (tx, &*fresh_tp.insert(tp))
                };
                let mut st = #guess;
                let mut report = #rt::NewtonReport::new();
                let fixed = #rt::Fixed { x, xd, xdd, tx: &tx, tp };
                let (qd, qdd, points) = self.#motion(fixed, &mut st, options, &mut report, #extra_names)?;
                t.update(x, xd, xdd, &st, qd, qdd, points, report, tx, fresh_tp.as_ref().map(|tp| (&params, tp)));
                Ok(())
            }
        }
    };
    let mut ticks = tick_fn(
        "tick_arrays",
        "motion_cached",
        (TokenStream::new(), TokenStream::new()),
        TokenStream::new(),
        quote! {
            /// One simulator tick to the inputs `x` (rates `xd`, `xdd`): the unknowns of Newton
            /// blocks predicted by a second-order step from the last tick, their sines and cosines
            /// rotated from the cached ones (recomputed every `mechgen::runtime::tick::RESYNC_TICKS` ticks or
            /// when the params changed); closed-form blocks solved on the last tick's branch; then
            /// velocities, accelerations and points. On error `t` is unchanged.
        },
    );
    if !(c.system.bodies.is_empty() && c.system.gravity.is_none()) {
        ticks.extend(tick_fn(
            "tick_dynamics_arrays",
            "motion_bodies_cached",
            (quote!(<S: #rt::BodySink<#gt>>), quote!(sink: &mut S)),
            quote!(sink),
            quote! {
                /// `tick_arrays` that hands gravity and every body's mass properties and motion to
                /// `sink`, computed in the same body as the points (sharing their
                /// subexpressions). On error `t` is unchanged. Inlined, so that the sink's sums
                /// stay in registers and the caller's totals follow them.
                #[inline]
            },
        ));
    }
    quote! {
        #block_fns

        /// Sines and cosines of the inputs and params that appear in a sin or cos.
        #[inline]
        fn trig_fixed(&self, x: &[#gt; #ni]) -> #rt::TrigFixed<#gt, #ni, #npar> {
            #params_let
            let #tx_mut tx: [(#gt, #gt); #ni] = #tx_init;
            let #tp_mut tp: [(#gt, #gt); #npar] = #tp_init;
            #tx_sets
            #tp_sets
            (tx, tp)
        }

        /// The unknowns with the sines and cosines the solvers read.
        #[inline]
        fn trig_state(q: [#gt; #nu]) -> #rt::TrigState<#gt, #nu> {
            #rt::TrigState::new(q, [#(#angle_mask),*])
        }

        #stages

        #motion
        #scene_methods

        /// Solves the positions block by block by Newton's method from the guess in `q`;
        /// on success `q` holds the solution on the guess's branch.
        pub fn solve_position(&self, x: &[#gt; #ni], q: &mut [#gt; #nu], options: &#rt::SolveOptions<#gt>)
            -> ::core::result::Result<#rt::NewtonReport<#gt>, #rt::SolveError> {
            #rt::check_finite(#rt::Quantity::Param, &self.params.to_array())?;
            #rt::check_finite(#rt::Quantity::Input, x)?;
            #rt::check_finite(#rt::Quantity::Guess, q)?;
            let (tx, tp) = self.trig_fixed(x);
            let mut st = Self::trig_state(*q);
            let mut report = #rt::NewtonReport::new();
            let zero = [#gt::zero(); #ni];
            let fixed = #rt::Fixed { x, xd: &zero, xdd: &zero, tx: &tx, tp: &tp };
            self.position_cached(fixed, &mut st, options, &mut report)?;
            *q = st.q;
            Ok(report)
        }

        /// q̇ from J q̇ = −Φx ẋ at a solved position. Non-finite arguments: `NonFinite` (params,
        /// inputs, positions, input rates, in that order).
        pub fn solve_velocity(&self, x: &[#gt; #ni], q: &[#gt; #nu], xd: &[#gt; #ni]) -> ::core::result::Result<[#gt; #nu], #rt::SolveError> {
            #rt::check_finite(#rt::Quantity::Param, &self.params.to_array())?;
            #rt::check_finite(#rt::Quantity::Input, x)?;
            #rt::check_finite(#rt::Quantity::Position, q)?;
            #rt::check_finite(#rt::Quantity::InputRate, xd)?;
            let (tx, tp) = self.trig_fixed(x);
            let st = Self::trig_state(*q);
            let zero = [#gt::zero(); #ni];
            self.velocity_cached(#rt::Fixed { x, xd, xdd: &zero, tx: &tx, tp: &tp }, &st)
        }

        /// q̈ from J q̈ = γ at a solved position and velocity. Non-finite arguments: `NonFinite`
        /// (params, inputs, positions, input rates, rates, input accelerations, in that order).
        pub fn solve_acceleration(&self, x: &[#gt; #ni], q: &[#gt; #nu], xd: &[#gt; #ni], qd: &[#gt; #nu], xdd: &[#gt; #ni])
            -> ::core::result::Result<[#gt; #nu], #rt::SolveError> {
            #rt::check_finite(#rt::Quantity::Param, &self.params.to_array())?;
            #rt::check_finite(#rt::Quantity::Input, x)?;
            #rt::check_finite(#rt::Quantity::Position, q)?;
            #rt::check_finite(#rt::Quantity::InputRate, xd)?;
            #rt::check_finite(#rt::Quantity::Rate, qd)?;
            #rt::check_finite(#rt::Quantity::InputAcceleration, xdd)?;
            let (tx, tp) = self.trig_fixed(x);
            let st = Self::trig_state(*q);
            self.acceleration_cached(#rt::Fixed { x, xd, xdd, tx: &tx, tp: &tp }, &st, qd)
        }

        /// Positions from the guess in `q`, then velocities, accelerations and points, sharing one
        /// set of sines and cosines: the fastest way to a full state (one simulator tick).
        #[inline]
        fn solve_arrays(&self, x: &[#gt; #ni], xd: &[#gt; #ni], xdd: &[#gt; #ni], q: &mut [#gt; #nu],
            options: &#rt::SolveOptions<#gt>)
            -> ::core::result::Result<#rt::RatesReport<#gt, #nu, #np>, #rt::SolveError> {
            #rt::check_finite(#rt::Quantity::Param, &self.params.to_array())?;
            #rt::check_finite(#rt::Quantity::Input, x)?;
            #rt::check_finite(#rt::Quantity::Guess, q)?;
            #rt::check_finite(#rt::Quantity::InputRate, xd)?;
            #rt::check_finite(#rt::Quantity::InputAcceleration, xdd)?;
            let (tx, tp) = self.trig_fixed(x);
            let mut st = Self::trig_state(*q);
            let mut report = #rt::NewtonReport::new();
            let fixed = #rt::Fixed { x, xd, xdd, tx: &tx, tp: &tp };
            let (qd, qdd, points) = self.motion_cached(fixed, &mut st, options, &mut report)?;
            *q = st.q;
            Ok((qd, qdd, points, report))
        }

        /// The first tick of a simulation: `solve_arrays` from `guess`, kept with its sines and
        /// cosines for `tick_arrays` (the typed `tick_start` and `tick` call these).
        fn tick_start_arrays(&self, x: &[#gt; #ni], xd: &[#gt; #ni], xdd: &[#gt; #ni], guess: &[#gt; #nu],
            options: &#rt::SolveOptions<#gt>) -> ::core::result::Result<#tick_ty<#gt>, #rt::SolveError> {
            use #rt::TickCache as _;
            let mut q = *guess;
            let (qd, qdd, points, report) = self.solve_arrays(x, xd, xdd, &mut q, options)?;
            let (tx, tp) = self.trig_fixed(x);
            let st = Self::trig_state(q);
            Ok(#rt::Tick::new(#rt::Solution { x: *x, xd: *xd, xdd: *xdd, q, qd, qdd, points, report,
                tx, tq: st.sc, tp, params: self.params.to_array() }))
        }

        #ticks
    }
}
