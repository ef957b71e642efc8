//! Stage 6d: a mechanism's bodies, for dynamics (only a mechanism with bodies or gravity has
//! these): every body's centre of mass and angle with their velocities and accelerations, and
//! gravity with every body's mass and inertia at the params, in one body on the sine and cosine
//! caches (`body_motion_cached`, handing them to a `BodySink`); `body_motion` and
//! `mass_properties` compute their own, `tick_bodies` reads a tick's.

use proc_macro2::{Ident, TokenStream};
use quote::quote;

use crate::analysis::Compiled;
use crate::emit::args::Args;
use crate::emit::body::body;
use crate::emit::cache::{Cached, trig_masks};
use crate::ir::dag::NodeId;

/// Gravity (when given), each body's mass and inertia, then each body's nine motion numbers
/// (centre x, y, angle; their velocities; their accelerations): the roots of every function that
/// computes bodies, and how many of them lead up to the motion (gravity and masses).
pub(crate) fn body_roots(c: &Compiled) -> (Vec<NodeId>, usize) {
    let (sys, d) = (&c.system, &c.derivatives);
    let mut roots: Vec<NodeId> = sys.gravity.into_iter().flatten().collect();
    roots.extend(sys.bodies.iter().flat_map(|n| [n.mass, n.inertia]));
    let nm = roots.len();
    for (b, n) in sys.bodies.iter().enumerate() {
        roots.extend([n.com[0], n.com[1], n.angle]);
        roots.extend(d.body_velocity[b]);
        roots.extend(d.body_acceleration[b]);
    }
    (roots, nm)
}

/// From the expressions of [`body_roots`] (or of its first part): gravity's expression, then each
/// body's `BodyMass { … }` and `BodyMotion { … }` expressions.
pub(crate) fn body_values(
    c: &Compiled,
    (rt, gt): (&TokenStream, &Ident),
    r: &[TokenStream],
) -> (TokenStream, Vec<TokenStream>, Vec<TokenStream>) {
    let nb = c.system.bodies.len();
    let (g, rest) = if c.system.gravity.is_some() {
        let (gx, gy) = (&r[0], &r[1]);
        (quote!([#gx, #gy]), &r[2..])
    } else {
        (quote!([#gt::zero(); 2]), r)
    };
    let (m, motion) = rest.split_at(2 * nb);
    let m = m.chunks(2).map(|b| {
        let (mass, inertia) = (&b[0], &b[1]);
        quote!(#rt::BodyMass { mass: #mass, inertia: #inertia })
    });
    let motion = motion.chunks(9).map(|b| {
        let (px, py, a, vx, vy, w, ax, ay, al) =
            (&b[0], &b[1], &b[2], &b[3], &b[4], &b[5], &b[6], &b[7], &b[8]);
        quote!(#rt::BodyMotion {
            com: #rt::PointMotion { position: [#px, #py], velocity: [#vx, #vy], acceleration: [#ax, #ay] },
            angle: [#a, #w, #al],
        })
    });
    (g, m.collect(), motion.collect())
}

/// From all the expressions of [`body_roots`]: gravity, then every body, handed to `sink` (a
/// `BodySink`).
pub(crate) fn body_sink_calls(
    c: &Compiled,
    (rt, gt): (&TokenStream, &Ident),
    r: &[TokenStream],
) -> TokenStream {
    let (g, m, motion) = body_values(c, (rt, gt), r);
    let calls = m
        .iter()
        .zip(&motion)
        .enumerate()
        .map(|(i, (m, b))| quote!(sink.body(#i, #m, #b);));
    quote!(sink.gravity(#g); #(#calls)*)
}

/// `body_motion_cached`, `body_motion`, `mass_properties` and `tick_bodies` (inside the mechanism
/// type's `impl<T: Real>` block); nothing for a mechanism without bodies or gravity.
pub(crate) fn body_fns(c: &Compiled, args: &Args) -> TokenStream {
    let sys = &c.system;
    if sys.bodies.is_empty() && sys.gravity.is_none() {
        return TokenStream::new();
    }
    let (rt, gt, tick_ty) = (&args.rt, &args.items.scalar, &args.items.tick);
    let (ni, nu, _, npar) = crate::emit::args::sizes(&c.model);
    let nb = sys.bodies.len();
    let dag = &sys.dag;
    let (roots, nm) = body_roots(c);
    let masses = &roots[..nm];
    let (xm, qm, pm) = trig_masks(c);
    let cached = Cached {
        args,
        x: xm,
        q: qm,
        p: pm,
    };
    let fused = body(dag, &roots, &cached);
    let fresh = body(dag, masses, args);
    let calls = body_sink_calls(c, (rt, gt), &fused.roots);
    let (fg, fm, _) = body_values(c, (rt, gt), &fresh.roots);
    let fm = fm.iter().enumerate().map(|(i, m)| quote!(masses[#i] = #m;));
    let (stmts, fresh_stmts) = (&fused.stmts, &fresh.stmts);
    let rates = quote!(x: &[#gt; #ni], q: &[#gt; #nu], xd: &[#gt; #ni], qd: &[#gt; #nu], xdd: &[#gt; #ni], qdd: &[#gt; #nu]);
    let inputs = quote!((x, xd, xdd): (&[#gt; #ni], &[#gt; #ni], &[#gt; #ni]));
    let unknowns = quote!((q, qd, qdd): (&[#gt; #nu], &[#gt; #nu], &[#gt; #nu]));
    let ctx = quote!((tx, tq, tp): #rt::TrigRefs<'_, #gt, #ni, #nu, #npar>);
    let arrays = quote!(([#rt::BodyMass::default(); #nb], [#rt::BodyMotion::default(); #nb], [#gt::zero(); 2]));
    quote! {
        /// Gravity, then every body's mass properties and motion, handed to `sink`, with the sines
        /// and cosines of the inputs, unknowns and params given.
        #[inline]
        fn body_motion_cached<S: #rt::BodySink<#gt>>(&self, #inputs, #unknowns, #ctx, sink: &mut S) {
            #stmts
            #calls
        }

        /// Each body's centre of mass and angle with their velocities and accelerations at a
        /// solved state, in `INFO.bodies` order.
        pub fn body_motion(&self, #rates) -> [#rt::BodyMotion<#gt>; #nb] {
            let (tx, tp) = self.trig_fixed(x);
            let st = Self::trig_state(*q);
            let mut arrays = #arrays;
            self.body_motion_cached((x, xd, xdd), (q, qd, qdd), (&tx, &st.sc, &tp), &mut arrays);
            arrays.1
        }

        /// The acceleration of gravity (zero without a `gravity` key) and each body's mass and
        /// inertia about its centre of mass at the params, in `INFO.bodies` order.
        pub fn mass_properties(&self) -> ([#gt; 2], [#rt::BodyMass<#gt>; #nb]) {
            let mut masses = [#rt::BodyMass::default(); #nb];
            #fresh_stmts
            #(#fm)*
            (#fg, masses)
        }

        /// [`Self::mass_properties`] and [`Self::body_motion`] at a tick's state handed to `sink`,
        /// with the sines and cosines the tick keeps (when the params are still those of the last
        /// tick; else computed afresh).
        #[inline]
        pub fn tick_bodies<S: #rt::BodySink<#gt>>(&self, t: &#tick_ty<#gt>, sink: &mut S) {
            use #rt::TickCache as _;
            if !t.same_params(&self.params.to_array()) {
                let (g, m) = self.mass_properties();
                let b = self.body_motion(&t.x, &t.q, &t.xd, &t.qd, &t.xdd, &t.qdd);
                sink.gravity(g);
                for (k, (m, b)) in m.into_iter().zip(b).enumerate() {
                    sink.body(k, m, b);
                }
                return;
            }
            let (tx, tq) = t.trig();
            self.body_motion_cached((&t.x, &t.xd, &t.xdd), (&t.q, &t.qd, &t.qdd), (tx, tq, t.params_trig()), sink)
        }
    }
}
