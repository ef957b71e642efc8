//! Stage 6c: the whole-system functions of one mechanism's type: Φ, J, Φx, J̇, −Φx ẋ, γ and the
//! points, each a straight-line function of (x, q, …) that computes its own trigonometry (the
//! public evaluation API; the solvers in `emit_solve` read theirs from caches).

use proc_macro2::TokenStream;
use quote::{format_ident, quote};

use crate::analysis::Compiled;
use crate::emit::args::{Args, equation_name};
use crate::emit::body::body;
use crate::emit::comments::comment;
use crate::ir::dag::NodeId;

/// The whole-system methods (inside the mechanism type's `impl<T: Real>` block).
pub(crate) fn system_fns(c: &Compiled, args: &Args) -> TokenStream {
    let (rt, gt) = (&args.rt, &args.items.scalar);
    let m = &c.model;
    let dag = &c.system.dag;
    let (ni, nu, np) = (m.inputs.len(), m.unknowns.len(), m.points.len());
    let equation_rows = |r: usize| (format!("Φ{r}"), format!(" ({})", equation_name(m, r)));
    let point_rows = |r: usize| {
        let axis = if r.is_multiple_of(2) { "x" } else { "y" };
        (format!("{}_{axis}", m.points[r / 2].0.text), String::new())
    };
    let matrix_fn = |fname: &str,
                     doc: &str,
                     entries: &[Vec<NodeId>],
                     cols: usize,
                     col_names: &[String],
                     extra: TokenStream,
                     row_name: &dyn Fn(usize) -> (String, String)| {
        let f = format_ident!("{}", fname);
        let rows = entries.len();
        let roots: Vec<NodeId> = entries.iter().flatten().copied().collect();
        let b = body(dag, &roots, args);
        let mut sets = TokenStream::new();
        let mut written = false;
        for (r, row) in entries.iter().enumerate() {
            for (k, &e) in row.iter().enumerate() {
                if dag.is_zero(e) {
                    continue;
                }
                let v = &b.roots[r * cols + k];
                let (row, note) = row_name(r);
                sets.extend(comment(&format!(
                    "[{r}][{k}] = ∂{row}/∂{}{note}",
                    col_names[k]
                )));
                sets.extend(quote!(m[(#r, #k)] = #v;));
                written = true;
            }
        }
        let stmts = b.stmts;
        // A structurally zero matrix is returned as is.
        let matrix = if written {
            quote! {
                let mut m = #rt::nalgebra::SMatrix::<#gt, #rows, #cols>::zeros();
                #sets
                m
            }
        } else {
            quote!(#rt::nalgebra::SMatrix::<#gt, #rows, #cols>::zeros())
        };
        quote! {
            #[doc = #doc]
            pub fn #f(&self, x: &[#gt; #ni], q: &[#gt; #nu] #extra) -> #rt::nalgebra::SMatrix<#gt, #rows, #cols> {
                #stmts
                #matrix
            }
        }
    };
    let unknown_names: Vec<String> = m.unknowns.iter().map(|u| u.name.text.clone()).collect();
    let input_names: Vec<String> = m.inputs.iter().map(|u| u.name.text.clone()).collect();
    let rates = quote!(, xd: &[#gt; #ni], qd: &[#gt; #nu]);
    let jacobian = matrix_fn(
        "jacobian",
        "J = ∂Φ/∂q at (x, q).",
        &c.derivatives.jacobian,
        nu,
        &unknown_names,
        quote!(),
        &equation_rows,
    );
    let input_jacobian = matrix_fn(
        "input_jacobian",
        "Φx = ∂Φ/∂x at (x, q).",
        &c.derivatives.input_jacobian,
        ni,
        &input_names,
        quote!(),
        &equation_rows,
    );
    let jacobian_dot = matrix_fn(
        "jacobian_dot",
        "J̇ = dJ/dt at (x, q, ẋ, q̇).",
        &c.derivatives.jacobian_dot,
        nu,
        &unknown_names,
        rates,
        &equation_rows,
    );
    let param_names: Vec<String> = m.params.iter().map(|p| p.name.text.clone()).collect();
    let param_jacobian = matrix_fn(
        "param_jacobian",
        "Φp = ∂Φ/∂p at (x, q), over the params of `Params` (derived params differentiated through).",
        &c.derivatives.param_jacobian,
        m.params.len(),
        &param_names,
        quote!(),
        &equation_rows,
    );
    let point_rows_of = |per_point: &[[Vec<NodeId>; 2]]| -> Vec<Vec<NodeId>> {
        per_point.iter().flat_map(|p| p.iter().cloned()).collect()
    };
    let point_jacobian = matrix_fn(
        "point_jacobian",
        "∂P/∂q at (x, q): rows `P_x`, `P_y` per point in `POINT_NAMES` order.",
        &point_rows_of(&c.derivatives.point_jacobian),
        nu,
        &unknown_names,
        quote!(),
        &point_rows,
    );
    let point_param_jacobian = matrix_fn(
        "point_param_jacobian",
        "∂P/∂p at (x, q): rows `P_x`, `P_y` per point, over the params of `Params`.",
        &point_rows_of(&c.derivatives.point_param_jacobian),
        m.params.len(),
        &param_names,
        quote!(),
        &point_rows,
    );

    let vector_fn = |fname: &str,
                     doc: &str,
                     roots: &[NodeId],
                     params: TokenStream,
                     ret: TokenStream,
                     wrap: &dyn Fn(&[TokenStream]) -> TokenStream| {
        let f = format_ident!("{}", fname);
        let b = body(dag, roots, args);
        let stmts = b.stmts;
        let value = wrap(&b.roots);
        quote! {
            #[doc = #doc]
            pub fn #f(&self, #params) -> #ret { #stmts #value }
        }
    };
    let array = |r: &[TokenStream]| quote!([#(#r),*]);
    let svector = |r: &[TokenStream]| quote!(#rt::nalgebra::SVector::from([#(#r),*]));
    let residual = vector_fn(
        "residual",
        "Φ(x, q): the loop-closure residuals, two per loop (x then y).",
        &c.system.residuals,
        quote!(x: &[#gt; #ni], q: &[#gt; #nu]),
        quote!([#gt; #nu]),
        &array,
    );
    let velocity_rhs = vector_fn(
        "velocity_rhs",
        "−Φx ẋ: the right-hand side of J q̇ = −Φx ẋ.",
        &c.derivatives.velocity_rhs,
        quote!(x: &[#gt; #ni], q: &[#gt; #nu], xd: &[#gt; #ni]),
        quote!(#rt::nalgebra::SVector<#gt, #nu>),
        &svector,
    );
    let acceleration_rhs = vector_fn(
        "acceleration_rhs",
        "γ = −(J̇ q̇ + Φ̇x ẋ) − Φx ẍ: the right-hand side of J q̈ = γ.",
        &c.derivatives.acceleration_rhs,
        quote!(x: &[#gt; #ni], q: &[#gt; #nu], xd: &[#gt; #ni], qd: &[#gt; #nu], xdd: &[#gt; #ni]),
        quote!(#rt::nalgebra::SVector<#gt, #nu>),
        &svector,
    );
    let pos_roots: Vec<NodeId> = c.system.points.iter().flatten().copied().collect();
    let point_positions = vector_fn(
        "point_positions",
        "Positions of the points, in `POINT_NAMES` order.",
        &pos_roots,
        quote!(x: &[#gt; #ni], q: &[#gt; #nu]),
        quote!([[#gt; 2]; #np]),
        &|r: &[TokenStream]| {
            let pairs = r.chunks(2).map(|p| {
                let (a, b) = (&p[0], &p[1]);
                quote!([#a, #b])
            });
            quote!([#(#pairs),*])
        },
    );
    let mut motion_roots = Vec::new();
    for p in 0..np {
        motion_roots.extend(c.system.points[p]);
        motion_roots.extend(c.derivatives.point_velocity[p]);
        motion_roots.extend(c.derivatives.point_acceleration[p]);
    }
    let point_motion = vector_fn(
        "point_motion",
        "Position, velocity and acceleration of every point, in `POINT_NAMES` order.",
        &motion_roots,
        quote!(x: &[#gt; #ni], q: &[#gt; #nu], xd: &[#gt; #ni], qd: &[#gt; #nu], xdd: &[#gt; #ni], qdd: &[#gt; #nu]),
        quote!([#rt::PointMotion<#gt>; #np]),
        &|r: &[TokenStream]| {
            let items = r.chunks(6).map(|p| {
                let (px, py, vx, vy, ax, ay) = (&p[0], &p[1], &p[2], &p[3], &p[4], &p[5]);
                quote!(#rt::PointMotion { position: [#px, #py], velocity: [#vx, #vy], acceleration: [#ax, #ay] })
            });
            quote!([#(#items),*])
        },
    );

    quote! {
        #residual
        #jacobian
        #input_jacobian
        #jacobian_dot
        #param_jacobian
        #point_jacobian
        #point_param_jacobian
        #velocity_rhs
        #acceleration_rhs
        #point_positions
        #point_motion
    }
}
