//! Stage 6 (shared by the block solvers and the fused body): the call of a closed-form block's
//! runtime kernel (`solve_dyad`, `closed_form::solve_*`) on its roots, and which unknowns the
//! closed forms solve (they skip a tick's predictor). The table of kinds and calls is the
//! closed-form section of docs/internals.md.

use proc_macro2::TokenStream;
use quote::quote;

use crate::analysis::Compiled;
use crate::analysis::closed_form::ClosedForm;

/// Which angle values a kernel computes: all of them (a mechanism's solvers), or, for a scene,
/// those it reads (`read[k]`, `ScenePlan::values_read`) and the others only when the `bool`
/// expression `every` (the scene body's `every_angle` argument) says so. Every kind with an
/// angle (RRR, RRP, RPR, one angle) can skip it; lengths are always computed.
#[derive(Clone, Copy)]
pub(crate) enum AngleValues<'a> {
    All,
    Read {
        read: &'a [bool],
        every: &'a TokenStream,
    },
}

/// `rt::…::solve_*(bi, st, …)?;` for the closed form `cf` of block `bi`, whose roots (in the
/// kind's order, `ClosedForm::roots`) are the expressions `r`; `scale` is the length scale's
/// expression (asked for only to report a gap). Reads `self`, `options`, `report`.
pub(crate) fn kernel_call(
    rt: &TokenStream,
    bi: usize,
    cf: &ClosedForm,
    r: &[TokenStream],
    values: AngleValues,
    scale: &TokenStream,
) -> TokenStream {
    let sc = quote!(|| #scale);
    let tol = quote!(options.newton.tolerance);
    // Whether the kernel computes angle `k`'s value: `true`, or `every_angle` where nothing reads it.
    let value = |k: usize| match values {
        AngleValues::Read { read, every } if !read[k] => every.clone(),
        _ => quote!(true),
    };
    match cf {
        ClosedForm::Rrr(d) => {
            let (a, b) = (d.a, d.b);
            let [kx, ky, pa, ra, pb, rb] = [0, 1, 2, 3, 4, 5].map(|i| &r[i]);
            match values {
                AngleValues::Read { read, .. } if !(read[a] && read[b]) => {
                    let (va, vb) = (value(a), value(b));
                    quote!(#rt::solve_dyad_angles(#bi, st, #a, #b, [#kx, #ky], (#pa, #ra), (#pb, #rb), #sc, #tol, report, [#va, #vb])?;)
                }
                _ => {
                    quote!(#rt::solve_dyad(#bi, st, #a, #b, [#kx, #ky], (#pa, #ra), (#pb, #rb), #sc, #tol, report)?;)
                }
            }
        }
        ClosedForm::Rrp { q, s, .. } => {
            let [kx, ky, p, rr, ux, uy] = [0, 1, 2, 3, 4, 5].map(|i| &r[i]);
            let v = value(*q);
            quote!(#rt::closed_form::solve_rrp(#bi, st, #q, #s, [#kx, #ky], (#p, #rr), [#ux, #uy], #sc, #tol, report, #v)?;)
        }
        ClosedForm::Rpr { q, s, .. } => {
            let [kx, ky, mp, mr, np, nr] = [0, 1, 2, 3, 4, 5].map(|i| &r[i]);
            let v = value(*q);
            quote!(#rt::closed_form::solve_rpr(#bi, st, #q, #s, [#kx, #ky], (#mp, #mr), (#np, #nr), #sc, #tol, report, #v)?;)
        }
        ClosedForm::Linear2 { s1, s2, .. } => {
            let [kx, ky, ax, ay, bx, by] = [0, 1, 2, 3, 4, 5].map(|i| &r[i]);
            quote!(#rt::closed_form::solve_linear2(#bi, st, (#s1, #s2), [#kx, #ky], [#ax, #ay], [#bx, #by], report)?;)
        }
        ClosedForm::Angle1 { q, .. } => {
            let [k, p, qq] = [0, 1, 2].map(|i| &r[i]);
            let v = value(*q);
            quote!(#rt::closed_form::solve_angle1(#bi, st, #q, #k, (#p, #qq), #sc, #tol, report, #v)?;)
        }
        ClosedForm::Length1 { s, .. } => {
            let [k, a] = [0, 1].map(|i| &r[i]);
            quote!(#rt::closed_form::solve_length1(#bi, st, #s, #k, #a)?;)
        }
    }
}

/// Per unknown: whether a closed-form block solves it (a tick keeps it from the last tick
/// instead of predicting it).
pub(crate) fn closed_mask(c: &Compiled) -> Vec<bool> {
    let mut mask = vec![false; c.model.unknowns.len()];
    for cf in c.blocks.iter().filter_map(|b| b.closed_form.as_ref()) {
        for &u in &cf.slots()[..cf.kind().unknowns()] {
            mask[u] = true;
        }
    }
    mask
}

/// How the generated code's comments name a block's kind.
pub(crate) fn kind_text(cf: &ClosedForm) -> String {
    match cf {
        ClosedForm::Rrr(_) => "closed form (a dyad)".to_string(),
        cf => format!("closed form ({})", cf.name()),
    }
}
