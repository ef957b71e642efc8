//! Stage 6 (emit), one mechanism's module: its static description, the `Params`, `Inputs`,
//! `Unknowns`, `Points`, `Motion` structs and `Tick` alias (named by the names table around the
//! mechanism's type), the mechanism type with its whole-system functions ([`crate::emit::system`])
//! and solvers ([`crate::emit::solve`]), its typed `solve`, `tick_start` and `tick`, and its
//! `StaticMechanism` impl.

use proc_macro2::{Ident, TokenStream};
use quote::{format_ident, quote};

use crate::analysis::Compiled;
use crate::emit::args::Args;
use crate::emit::names::ModuleItems;
use crate::sema::model::Kind;

fn f64_lit(x: f64) -> proc_macro2::Literal {
    proc_macro2::Literal::f64_unsuffixed(x)
}

/// The runtime's `Kind` variant, named as it is (the generator's `Kind` is the runtime's).
fn kind(k: Kind, rt: &TokenStream) -> TokenStream {
    let variant = format_ident!("{k:?}");
    quote!(#rt::Kind::#variant)
}

pub(crate) fn module(c: &Compiled, rt: &TokenStream) -> TokenStream {
    let m = &c.model;
    let args = Args {
        model: m,
        rt: rt.clone(),
        items: ModuleItems::new(&m.name.text),
    };
    let it = &args.items;
    let (ty, gt) = (&it.ty, &it.scalar);
    let (params_ty, inputs_ty, unknowns_ty) = (&it.params, &it.inputs, &it.unknowns);
    let (points_ty, tick_ty, motion_ty) = (&it.points, &it.tick, &it.motion);
    let (ni, nu, np, npar) = crate::emit::args::sizes(m);
    let np2 = 2 * np;
    let mod_name = format_ident!("{}", m.name.text);
    let name = &m.name.text;
    let doc = if m.description.is_empty() {
        format!("Mechanism `{name}`.")
    } else {
        m.description.clone()
    };

    // Static description.
    let coord_info = |cs: &[crate::sema::model::Coord]| -> Vec<TokenStream> {
        cs.iter()
            .map(|c| {
                let (n, k, s) = (&c.name.text, kind(c.kind, rt), f64_lit(c.start));
                quote!(#rt::CoordInfo { name: #n, kind: #k, start: #s })
            })
            .collect()
    };
    let inputs_info = coord_info(&m.inputs);
    let unknowns_info = coord_info(&m.unknowns);
    let params_info = m.params.iter().map(|p| {
        let (n, k, v) = (&p.name.text, kind(p.kind, rt), f64_lit(p.value));
        quote!(#rt::ParamInfo { name: #n, kind: #k, default: #v })
    });
    let point_names: Vec<&str> = m.points.iter().map(|(n, _)| n.text.as_str()).collect();
    let blocks_info = c.blocks.iter().map(|b| {
        let u = &b.block.unknowns;
        quote!(&[#(#u),*])
    });
    let closed_info = c.blocks.iter().map(|b| b.closed_form.is_some());
    let body_names = m.bodies.iter().map(|b| b.name.text.as_str());
    let description = &m.description;

    // Params struct.
    let param_fields: Vec<Ident> = m
        .params
        .iter()
        .map(|p| format_ident!("{}", p.name.text))
        .collect();
    let param_docs = m.params.iter().map(|p| {
        let k = if p.kind == Kind::Angle {
            "angle, radians"
        } else {
            "length"
        };
        match &p.source {
            Some(src) => format!("`{}` = {src} = {:?} ({k})", p.name.text, p.value),
            None => format!("`{}` = {:?} ({k})", p.name.text, p.value),
        }
    });
    let param_defaults = m.params.iter().map(|p| super::body::literal(p.value, gt));
    // A struct with no field of its own (no params, no points, …) still uses its type parameter.
    let marker = |n: usize| {
        (n == 0).then(|| quote!(#[doc(hidden)] pub _scalar: ::core::marker::PhantomData<#gt>,))
    };
    let marker_init = |n: usize| (n == 0).then(|| quote!(_scalar: ::core::marker::PhantomData,));
    let (params_marker, params_marker_init) = (marker(npar), marker_init(npar));
    let (points_marker, points_marker_init) = (marker(np), marker_init(np));
    let param_idx = 0..npar;
    let length_params: Vec<TokenStream> = m
        .params
        .iter()
        .filter(|p| p.kind == Kind::Length)
        .map(|p| {
            let p = format_ident!("{}", p.name.text);
            quote!(self.#p)
        })
        .collect();
    let length_scale = crate::emit::args::largest_length(gt, &length_params);

    let coords = |cs: &[crate::sema::model::Coord], ty: &Ident, what: &str| {
        let fields: Vec<Ident> = cs
            .iter()
            .map(|c| format_ident!("{}", c.name.text))
            .collect();
        let docs = cs.iter().map(|c| {
            format!(
                "`{}` ({})",
                c.name.text,
                if c.kind == Kind::Angle {
                    "angle, radians"
                } else {
                    "length"
                }
            )
        });
        let n = fields.len();
        let idx = 0..n;
        let doc = format!("The {what} of `{name}`, by name.");
        let (mk, mk_init) = (marker(n), marker_init(n));
        quote! {
            #[doc = #doc]
            #[derive(Clone, Copy, Debug, Default, PartialEq)]
            pub struct #ty<#gt> { #( #[doc = #docs] pub #fields: #gt, )* #mk }
            impl<#gt: ::core::marker::Copy> #ty<#gt> {
                pub fn from_array(a: [#gt; #n]) -> Self { #ty { #( #fields: a[#idx], )* #mk_init } }
                pub fn to_array(&self) -> [#gt; #n] { [#(self.#fields),*] }
            }
            impl<#gt: ::core::marker::Copy> ::core::convert::From<[#gt; #n]> for #ty<#gt> { fn from(a: [#gt; #n]) -> Self { Self::from_array(a) } }
            impl<#gt: ::core::marker::Copy> ::core::convert::From<#ty<#gt>> for [#gt; #n] { fn from(v: #ty<#gt>) -> Self { v.to_array() } }
        }
    };
    let inputs_struct = coords(&m.inputs, inputs_ty, "inputs");
    let unknowns_struct = coords(&m.unknowns, unknowns_ty, "unknowns");
    let point_fields: Vec<Ident> = point_names.iter().map(|n| format_ident!("{}", n)).collect();
    let point_idx = 0..np;

    // Why each allow of the module's `#![allow]` is there, as `//` lines below it.
    let allow_reasons: TokenStream = [
        "Allowed above, and why:",
        "non_snake_case: fields and locals keep the file's names (`E`, `sE`).",
    ]
    .iter()
    .map(|t| crate::emit::comments::comment(t))
    .collect();
    let system_fns = crate::emit::system::system_fns(c, &args);
    let body_fns = crate::emit::bodies::body_fns(c, &args);
    // A mechanism with bodies or gravity overrides the trait's bodiless defaults.
    let nb = m.bodies.len();
    let body_impls = if m.bodies.is_empty() && m.gravity.is_none() {
        TokenStream::new()
    } else {
        quote! {
            fn bodies(&self, input: &#rt::InputMotion<Self::X>, q: &Self::Q, qd: &Self::Q, qdd: &Self::Q,
                out: &mut [#rt::BodyMotion<#gt>]) -> ::core::result::Result<(), #rt::SolveError> {
                let b = #ty::body_motion(self, &input.x, q, &input.xd, qd, &input.xdd, qdd);
                #rt::put_slice(out, &b)
            }
            fn mass_properties(&self, out: &mut [#rt::BodyMass<#gt>]) -> ::core::result::Result<[#gt; 2], #rt::SolveError> {
                let (gravity, masses) = #ty::mass_properties(self);
                #rt::put_slice(out, &masses)?;
                Ok(gravity)
            }
            #[inline]
            fn with_tick_bodies<R>(&self, t: &Self::Tick, f: impl FnOnce(#rt::TickBodies<'_, #gt>) -> R) -> R {
                let mut arrays = ([#rt::BodyMass::default(); #nb], [#rt::BodyMotion::default(); #nb], [#gt::zero(); 2]);
                #ty::tick_bodies(self, t, &mut arrays);
                f((arrays.2, &arrays.0, &arrays.1))
            }
            #[inline]
            fn tick_with_bodies<R>(&self, t: &mut Self::Tick, input: &#rt::InputMotion<Self::X>, options: &#rt::SolveOptions<#gt>,
                f: impl FnOnce(&Self::Tick, #rt::TickBodies<'_, #gt>) -> ::core::result::Result<R, #rt::SolveError>)
                -> ::core::result::Result<R, #rt::SolveError> {
                let mut arrays = ([#rt::BodyMass::default(); #nb], [#rt::BodyMotion::default(); #nb], [#gt::zero(); 2]);
                #ty::tick_dynamics_arrays(self, t, &input.x, &input.xd, &input.xdd, options, &mut arrays)?;
                f(t, (arrays.2, &arrays.0, &arrays.1))
            }
            #[inline]
            fn tick_with_sink<S: #rt::BodySink<#gt>>(&self, t: &mut Self::Tick, input: &#rt::InputMotion<Self::X>,
                options: &#rt::SolveOptions<#gt>, sink: &mut S) -> ::core::result::Result<(), #rt::SolveError> {
                #ty::tick_dynamics_arrays(self, t, &input.x, &input.xd, &input.xdd, options, sink)
            }
        }
    };
    let solvers = crate::emit::solve::solvers(c, &args);
    let sensitivity_fns = crate::emit::sensitivity::sensitivity_fns(c, &args);
    let lanes = crate::emit::lane_items::mechanism(c, &args);
    let (lt, lanes_ty) = (&it.lane_scalar, &it.lanes);
    let nblocks = c.blocks.len();

    quote! {
        #[doc = #doc]
        pub mod #mod_name {
            #![allow(non_snake_case)]
            #allow_reasons

            /// Static description: names, kinds, start configuration, blocks.
            pub const INFO: #rt::StaticInfo = #rt::StaticInfo {
                name: #name,
                description: #description,
                inputs: &[#(#inputs_info),*],
                unknowns: &[#(#unknowns_info),*],
                params: &[#(#params_info),*],
                points: &[#(#point_names),*],
                blocks: &[#(#blocks_info),*],
                closed: &[#(#closed_info),*],
                bodies: &[#(#body_names),*],
            };
            /// Point names, in the order of point outputs.
            pub const POINT_NAMES: [&str; #np] = [#(#point_names),*];

            /// Params of the mechanism; `Default` holds the file's values. Change them at run time freely.
            #[derive(Clone, Copy, Debug, PartialEq)]
            pub struct #params_ty<#gt> { #( #[doc = #param_docs] pub #param_fields: #gt, )* #params_marker }
            impl<#gt: #rt::Real> ::core::default::Default for #params_ty<#gt> {
                fn default() -> Self { #params_ty { #( #param_fields: #param_defaults, )* #params_marker_init } }
            }
            impl<#gt: #rt::Real> #params_ty<#gt> {
                /// All params in file order.
                pub fn to_array(&self) -> [#gt; #npar] { [#(self.#param_fields),*] }
                /// Params from an array in file order (see `INFO.params` for names and kinds).
                pub fn from_array(a: [#gt; #npar]) -> Self { #params_ty { #( #param_fields: a[#param_idx], )* #params_marker_init } }
                /// The largest length param (1 when there is none): tolerances on lengths are relative to it.
                pub fn length_scale(&self) -> #gt {
                    #length_scale
                }
            }

            #inputs_struct
            #unknowns_struct

            /// Every point's motion, by name.
            #[derive(Clone, Copy, Debug, Default, PartialEq)]
            pub struct #points_ty<#gt> { #( pub #point_fields: #rt::PointMotion<#gt>, )* #points_marker }
            impl<#gt: ::core::marker::Copy> #points_ty<#gt> {
                pub fn from_array(a: [#rt::PointMotion<#gt>; #np]) -> Self { #points_ty { #( #point_fields: a[#point_idx], )* #points_marker_init } }
            }

            /// The state between simulator ticks (see `tick_start` and `tick`).
            pub type #tick_ty<#gt> = #rt::Tick<#gt, #ni, #nu, #np, #npar>;

            /// A solved state with named fields (`mechgen::State`): inputs and unknowns with their
            /// first and second time derivatives, the points and the position solve's report.
            pub type #motion_ty<#gt> = #rt::State<#inputs_ty<#gt>, #unknowns_ty<#gt>, #points_ty<#gt>, #gt>;

            #[doc = #doc]
            #[derive(Clone, Copy, Debug, PartialEq)]
            pub struct #ty<#gt = f64> { pub params: #params_ty<#gt> }
            impl<#gt: #rt::Real> ::core::default::Default for #ty<#gt> {
                fn default() -> Self { #ty { params: <#params_ty<#gt> as ::core::default::Default>::default() } }
            }

            impl<#gt: #rt::Real> #ty<#gt> {
                pub const INPUTS: usize = #ni;
                pub const UNKNOWNS: usize = #nu;
                pub const POINTS: usize = #np;
                pub const BLOCKS: usize = #nblocks;

                pub fn new(params: #params_ty<#gt>) -> Self { #ty { params } }

                /// The file's `start` configuration (on the wanted assembly branch).
                pub fn start() -> (#inputs_ty<#gt>, #unknowns_ty<#gt>) {
                    let x: [#gt; #ni] = ::core::array::from_fn(|i| #gt::lit(INFO.inputs[i].start));
                    let q: [#gt; #nu] = ::core::array::from_fn(|i| #gt::lit(INFO.unknowns[i].start));
                    (#inputs_ty::from_array(x), #unknowns_ty::from_array(q))
                }

                #system_fns
                #body_fns
                #solvers
                #sensitivity_fns

                /// One whole tick from `guess`: positions, velocities, accelerations and points,
                /// sharing one set of sines and cosines between the stages.
                pub fn solve(&self, input: &#rt::InputMotion<#inputs_ty<#gt>>, guess: &#unknowns_ty<#gt>, options: &#rt::SolveOptions<#gt>)
                    -> ::core::result::Result<#motion_ty<#gt>, #rt::SolveError> {
                    let mut q = guess.to_array();
                    let (qd, qdd, points, report) = self.solve_arrays(&input.x.to_array(), &input.xd.to_array(), &input.xdd.to_array(), &mut q, options)?;
                    Ok(#motion_ty { x: input.x, xd: input.xd, xdd: input.xdd, q: #unknowns_ty::from_array(q), qd: #unknowns_ty::from_array(qd),
                        qdd: #unknowns_ty::from_array(qdd), points: #points_ty::from_array(points), report })
                }

                /// [`Self::solve`] into `state`: its inputs and rates are the input, its unknowns
                /// the guess; on success it holds the solution, on error it is unchanged.
                pub fn solve_in_place(&self, state: &mut #motion_ty<#gt>, options: &#rt::SolveOptions<#gt>)
                    -> ::core::result::Result<(), #rt::SolveError> {
                    *state = self.solve(&state.input(), &state.q, options)?;
                    Ok(())
                }

                /// The first tick of a simulation, solved from `guess` and kept with its sines and
                /// cosines for [`Self::tick`] (see `Tick` for what the state holds).
                pub fn tick_start(&self, input: &#rt::InputMotion<#inputs_ty<#gt>>, guess: &#unknowns_ty<#gt>, options: &#rt::SolveOptions<#gt>)
                    -> ::core::result::Result<#tick_ty<#gt>, #rt::SolveError> {
                    self.tick_start_arrays(&input.x.to_array(), &input.xd.to_array(), &input.xdd.to_array(), &guess.to_array(), options)
                }

                /// The state a tick keeps, with the named access of [`Self::solve`]'s result
                /// (`Sixbar::motion(&t).points.E`): the last tick's inputs and their rates, the
                /// unknowns with their rates, the points and the report.
                pub fn motion(t: &#tick_ty<#gt>) -> #motion_ty<#gt> {
                    #motion_ty { x: #inputs_ty::from_array(t.x), xd: #inputs_ty::from_array(t.xd), xdd: #inputs_ty::from_array(t.xdd),
                        q: #unknowns_ty::from_array(t.q), qd: #unknowns_ty::from_array(t.qd), qdd: #unknowns_ty::from_array(t.qdd),
                        points: #points_ty::from_array(t.points), report: t.report }
                }

                /// One simulator tick to `input`: the unknowns of Newton blocks predicted by a
                /// second-order step from the last tick, their sines and cosines rotated from the
                /// cached ones (recomputed every `mechgen::runtime::tick::RESYNC_TICKS` ticks or when
                /// the params changed); closed-form blocks solved on the last tick's branch; then
                /// velocities, accelerations and points. On error `t` is unchanged.
                #[inline]
                pub fn tick(&self, t: &mut #tick_ty<#gt>, input: &#rt::InputMotion<#inputs_ty<#gt>>, options: &#rt::SolveOptions<#gt>)
                    -> ::core::result::Result<(), #rt::SolveError> {
                    self.tick_arrays(t, &input.x.to_array(), &input.xd.to_array(), &input.xdd.to_array(), options)
                }
            }

            impl<#gt: #rt::Real> #rt::StaticMechanism<#gt> for #ty<#gt> {
                const NAME: &'static str = #name;
                const INPUTS: usize = #ni;
                const UNKNOWNS: usize = #nu;
                const POINTS: usize = #np;
                type X = [#gt; #ni];
                type Q = [#gt; #nu];
                type Points = [#rt::PointMotion<#gt>; #np];
                type Jacobian = #rt::nalgebra::SMatrix<#gt, #nu, #nu>;
                type InputJacobian = #rt::nalgebra::SMatrix<#gt, #nu, #ni>;
                type ParamJacobian = #rt::nalgebra::SMatrix<#gt, #nu, #npar>;
                type PointParamJacobian = #rt::nalgebra::SMatrix<#gt, #np2, #npar>;
                type Tick = #tick_ty<#gt>;
                type Lanes<#lt: #rt::Lanes<Scalar = #gt>> = #lanes_ty<#lt>;
                fn info(&self) -> &'static #rt::StaticInfo { &INFO }
                fn with_params(params: &[#gt]) -> ::core::option::Option<Self> {
                    <[#gt; #npar]>::try_from(params).ok().map(|a| #ty::new(#params_ty::from_array(a)))
                }
                fn residual(&self, x: &Self::X, q: &Self::Q) -> Self::Q { #ty::residual(self, x, q) }
                fn jacobian(&self, x: &Self::X, q: &Self::Q) -> Self::Jacobian { #ty::jacobian(self, x, q) }
                fn input_jacobian(&self, x: &Self::X, q: &Self::Q) -> Self::InputJacobian { #ty::input_jacobian(self, x, q) }
                fn jacobian_dot(&self, x: &Self::X, q: &Self::Q, xd: &Self::X, qd: &Self::Q) -> Self::Jacobian {
                    #ty::jacobian_dot(self, x, q, xd, qd)
                }
                fn acceleration_rhs(&self, x: &Self::X, q: &Self::Q, xd: &Self::X, qd: &Self::Q, xdd: &Self::X) -> Self::Q {
                    #ty::acceleration_rhs(self, x, q, xd, qd, xdd).into()
                }
                fn solve_position(&self, x: &Self::X, q: &mut Self::Q, options: &#rt::SolveOptions<#gt>)
                    -> ::core::result::Result<#rt::NewtonReport<#gt>, #rt::SolveError> { #ty::solve_position(self, x, q, options) }
                fn solve_velocity(&self, x: &Self::X, q: &Self::Q, xd: &Self::X) -> ::core::result::Result<Self::Q, #rt::SolveError> {
                    #ty::solve_velocity(self, x, q, xd)
                }
                fn solve_acceleration(&self, x: &Self::X, q: &Self::Q, xd: &Self::X, qd: &Self::Q, xdd: &Self::X)
                    -> ::core::result::Result<Self::Q, #rt::SolveError> { #ty::solve_acceleration(self, x, q, xd, qd, xdd) }
                fn sensitivities(&self, x: &Self::X, q: &Self::Q)
                    -> ::core::result::Result<#rt::Sensitivities<Self::ParamJacobian, Self::PointParamJacobian>, #rt::SolveError> {
                    #ty::sensitivities(self, x, q)
                }
                fn tick_sensitivities(&self, t: &Self::Tick)
                    -> ::core::result::Result<#rt::Sensitivities<Self::ParamJacobian, Self::PointParamJacobian>, #rt::SolveError> {
                    #ty::tick_sensitivities(self, t)
                }
                fn points(&self, input: &#rt::InputMotion<Self::X>, q: &Self::Q, qd: &Self::Q, qdd: &Self::Q) -> Self::Points {
                    #ty::point_motion(self, &input.x, q, &input.xd, qd, &input.xdd, qdd)
                }
                #body_impls
                #[inline]
                fn solve(&self, input: &#rt::InputMotion<Self::X>, guess: &Self::Q, options: &#rt::SolveOptions<#gt>)
                    -> ::core::result::Result<#rt::StateOf<Self, #gt>, #rt::SolveError> {
                    let mut q = *guess;
                    let (qd, qdd, points, report) = #ty::solve_arrays(self, &input.x, &input.xd, &input.xdd, &mut q, options)?;
                    Ok(#rt::State { x: input.x, xd: input.xd, xdd: input.xdd, q, qd, qdd, points, report })
                }
                fn tick_start(&self, input: &#rt::InputMotion<Self::X>, guess: &Self::Q, options: &#rt::SolveOptions<#gt>)
                    -> ::core::result::Result<Self::Tick, #rt::SolveError> { #ty::tick_start_arrays(self, &input.x, &input.xd, &input.xdd, guess, options) }
                #[inline]
                fn tick(&self, t: &mut Self::Tick, input: &#rt::InputMotion<Self::X>, options: &#rt::SolveOptions<#gt>)
                    -> ::core::result::Result<(), #rt::SolveError> { #ty::tick_arrays(self, t, &input.x, &input.xd, &input.xdd, options) }
            }

            #lanes
        }
    }
}
