//! Stage 6e: each block's residual in double-word arithmetic (`blockB_residual_twofold`, the
//! runtime's `Twofold`), and the refinement the position steps run near a dead point: per block,
//! one Newton step with that residual (`refine_block`), which takes the positions from "good to
//! rounding over σ" to rounding of the unknowns themselves, so the rates there are accurate too.

use proc_macro2::TokenStream;
use quote::{format_ident, quote};

use crate::analysis::Compiled;
use crate::emit::args::Args;
use crate::ir::dag::{Func, Node, NodeId, Var};

/// The nodes `roots` reach, children before parents (ids increase from children to parents).
fn cone(c: &Compiled, roots: &[NodeId]) -> Vec<NodeId> {
    let dag = &c.system.dag;
    let mut seen = vec![false; dag.len()];
    let mut stack: Vec<NodeId> = roots.to_vec();
    while let Some(n) = stack.pop() {
        if std::mem::replace(&mut seen[n.index()], true) {
            continue;
        }
        stack.extend(dag.node(n).children());
    }
    (0..dag.len())
        .filter(|&i| seen[i])
        .map(|i| NodeId(i as u32))
        .collect()
}

/// `fn blockB_residual_twofold(&self, x, q) -> SVector<T, k>` for every block: the block's
/// residuals evaluated in double-word arithmetic from the exact inputs, unknowns and params,
/// rounded to `T` at the end.
pub(crate) fn residual_fns(c: &Compiled, args: &Args) -> TokenStream {
    let (rt, gt, m) = (&args.rt, &args.items.scalar, &c.model);
    let dag = &c.system.dag;
    let (ni, nu, _, npar) = crate::emit::args::sizes(m);
    let tw = quote!(#rt::Twofold);
    let mut out = TokenStream::new();
    for (bi, bf) in c.blocks.iter().enumerate() {
        let k = bf.block.unknowns.len();
        let nodes = cone(c, &bf.residual);
        // Which arguments' sine and cosine are read: computed once, right after the argument.
        let mut reads = vec![(false, false); dag.len()];
        for &n in &nodes {
            match dag.node(n) {
                Node::Sin(a) => reads[a.index()].0 = true,
                Node::Cos(a) => reads[a.index()].1 = true,
                Node::Tan(a) => reads[a.index()] = (true, true),
                _ => {}
            }
        }
        // Locals numbered in the order they are written (`w0`, `w1`, …); the sine and cosine of
        // `wK` are `sK` and `cK`.
        let mut number = vec![0usize; dag.len()];
        let mut next = 0;
        for &n in &nodes {
            if !matches!(dag.node(n), Node::Sin(_) | Node::Cos(_)) {
                number[n.index()] = next;
                next += 1;
            }
        }
        let w = |n: NodeId| match dag.node(n) {
            Node::Sin(a) => format_ident!("s{}", number[a.index()]),
            Node::Cos(a) => format_ident!("c{}", number[a.index()]),
            _ => format_ident!("w{}", number[n.index()]),
        };
        let mut stmts = TokenStream::new();
        for &n in &nodes {
            let value = match dag.node(n) {
                Node::Sin(_) | Node::Cos(_) => continue,
                Node::Const(bits) => {
                    let v = f64::from_bits(bits);
                    quote!(#tw::from(#v))
                }
                Node::Var(v) => {
                    let read = match v {
                        Var::X(i) => {
                            let i = i as usize;
                            quote!(x[#i])
                        }
                        Var::Q(i) => {
                            let i = i as usize;
                            quote!(q[#i])
                        }
                        Var::P(i) => {
                            let f = format_ident!("{}", m.params[i as usize].name.text);
                            quote!(self.params.#f)
                        }
                        // A residual reads positions only.
                        _ => quote!(#gt::zero()),
                    };
                    quote!(#tw::from(#read.to_f64()))
                }
                Node::Add(a, b) => {
                    let (a, b) = (w(a), w(b));
                    quote!(#a + #b)
                }
                Node::Sub(a, b) => {
                    let (a, b) = (w(a), w(b));
                    quote!(#a - #b)
                }
                Node::Mul(a, b) => {
                    let (a, b) = (w(a), w(b));
                    quote!(#a * #b)
                }
                Node::Div(a, b) => {
                    let (a, b) = (w(a), w(b));
                    quote!(#a / #b)
                }
                Node::Neg(a) => {
                    let a = w(a);
                    quote!(-#a)
                }
                Node::Tan(a) => {
                    let i = number[a.index()];
                    let (s, c) = (format_ident!("s{i}"), format_ident!("c{i}"));
                    quote!(#s / #c)
                }
                Node::Sqrt(a) => {
                    let a = w(a);
                    quote!(#a.sqrt())
                }
                // A params-only function, in f64 as the params' own values are.
                Node::Func(f, a, b) => {
                    let (a, b) = (w(a), w(b));
                    let call = match f {
                        Func::Asin => quote!(#a.value().asin()),
                        Func::Acos => quote!(#a.value().acos()),
                        Func::Atan => quote!(#a.value().atan()),
                        Func::Abs => quote!(#a.value().abs()),
                        Func::Atan2 => quote!(#a.value().atan2(#b.value())),
                        Func::Hypot => quote!(#a.value().hypot(#b.value())),
                    };
                    quote!(#tw::from(#call))
                }
            };
            let name = w(n);
            stmts.extend(quote!(let #name = #value;));
            let i = number[n.index()];
            let bind = |read: bool, prefix: &str| {
                let id = format_ident!("{prefix}{i}");
                if read { quote!(#id) } else { quote!(_) }
            };
            match reads[n.index()] {
                (false, false) => {}
                (s, c) => {
                    let (s, c) = (bind(s, "s"), bind(c, "c"));
                    stmts.extend(quote!(let (#s, #c) = #name.sin_cos();));
                }
            }
        }
        let roots = bf.residual.iter().map(|&r| {
            let r = w(r);
            quote!(#gt::lit(#r.value()))
        });
        let idx = &bf.block.unknowns;
        let (refine, pos) = (
            format_ident!("block{}_refine", bi),
            format_ident!("block{}_position", bi),
        );
        let refine_doc = format!(" Block {bi}: one Newton step with its double-word residual.");
        let fname = format_ident!("block{}_residual_twofold", bi);
        let doc = format!(
            " Block {bi}'s residuals in double-word arithmetic (refinement near a dead point)."
        );
        out.extend(quote! {
            #[doc = #doc]
            #[inline]
            fn #fname(&self, x: &[#gt; #ni], q: &[#gt; #nu]) -> #rt::nalgebra::SVector<#gt, #k> {
                #stmts
                #rt::nalgebra::SVector::from([#(#roots),*])
            }

            #[doc = #refine_doc]
            #[cold]
            #[inline(never)]
            fn #refine(&self, x: &[#gt; #ni], st: &mut #rt::TrigState<#gt, #nu>,
                tx: &[(#gt, #gt); #ni], tp: &[(#gt, #gt); #npar]) {
                let (_, jac) = self.#pos(x, &st.q, tx, tp, &st.sc);
                #rt::refine_block(st, [#(#idx),*], jac, self.#fname(x, &st.q));
            }
        });
    }
    out
}

/// The refinement after the position steps of `blocks`: when the solve's pivot ratio says the
/// state is near a dead point, one Newton step per block with its double-word residual.
pub(crate) fn refine_step(
    blocks: &[crate::analysis::structure::BlockId],
    rt: &TokenStream,
    gt: &proc_macro2::Ident,
) -> TokenStream {
    let steps = blocks.iter().map(|&bi| {
        let refine = format_ident!("block{}_refine", bi.index());
        quote!(self.#refine(x, st, tx, tp);)
    });
    quote! {
        if report.pivot_ratio < #gt::lit(#rt::REFINE_BELOW) {
            #(#steps)*
        }
    }
}
