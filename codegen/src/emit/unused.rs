//! Stage 6, unused parameters: generated functions of one family share a signature (a block's
//! functions take every input, unknown and cache) and each reads only some of it. Before
//! printing, every function's parameter that its body never names is renamed `_name`, and a
//! body's leading `let Struct { a, b, .. } = ...;` keeps only the fields the rest of the body
//! names, so the generated code needs no `unused_variables` allow.

use std::collections::HashSet;

use proc_macro2::{TokenStream, TokenTree};
use quote::ToTokens;
use syn::visit_mut::VisitMut;

/// Every identifier in `tokens`, at any depth.
fn idents(tokens: TokenStream, out: &mut HashSet<String>) {
    for t in tokens {
        match t {
            TokenTree::Ident(i) => {
                out.insert(i.to_string());
            }
            TokenTree::Group(g) => idents(g.stream(), out),
            _ => {}
        }
    }
}

/// Drops the fields that the rest of `body` never names from its top-level struct-pattern
/// `let`s (the pattern then ends in `..`).
fn prune_lets(body: &mut syn::Block) {
    for i in 0..body.stmts.len() {
        let is_struct_let = matches!(&body.stmts[i],
            syn::Stmt::Local(syn::Local { pat: syn::Pat::Struct(ps), .. }) if !ps.fields.is_empty());
        if !is_struct_let {
            continue;
        }
        let mut used = HashSet::new();
        for (j, stmt) in body.stmts.iter().enumerate() {
            if j != i {
                idents(stmt.to_token_stream(), &mut used);
            }
        }
        if let syn::Stmt::Local(syn::Local {
            pat: syn::Pat::Struct(ps),
            ..
        }) = &mut body.stmts[i]
        {
            let before = ps.fields.len();
            ps.fields = std::mem::take(&mut ps.fields)
                .into_pairs()
                .map(|p| p.into_value())
                .filter(|f| match &f.member {
                    syn::Member::Named(n) => used.contains(&n.to_string()),
                    syn::Member::Unnamed(_) => true,
                })
                .collect();
            if ps.fields.len() < before && ps.rest.is_none() {
                if !ps.fields.is_empty() {
                    ps.fields.push_punct(Default::default());
                }
                ps.rest = Some(syn::PatRest {
                    attrs: Vec::new(),
                    dot2_token: Default::default(),
                });
            }
        }
    }
}

/// Renames the names bound by `pat` (a name, or a tuple of them) that are not in `used`.
fn rename(pat: &mut syn::Pat, used: &HashSet<String>) {
    match pat {
        syn::Pat::Ident(pi) => {
            let name = pi.ident.to_string();
            if !name.starts_with('_') && !used.contains(&name) {
                pi.ident = syn::Ident::new(&format!("_{name}"), pi.ident.span());
                pi.mutability = None;
            }
        }
        syn::Pat::Tuple(t) => t.elems.iter_mut().for_each(|p| rename(p, used)),
        _ => {}
    }
}

/// Renames the parameters of `sig` (and the names of tuple parameters) that `body` does not
/// name.
fn mark(sig: &mut syn::Signature, body: &mut syn::Block) {
    prune_lets(body);
    let mut used = HashSet::new();
    idents(body.to_token_stream(), &mut used);
    for arg in &mut sig.inputs {
        if let syn::FnArg::Typed(pt) = arg {
            rename(pt.pat.as_mut(), &used);
        }
    }
}

/// The pass ([`VisitMut`]): free functions and methods alike.
pub(crate) struct Unused;

impl VisitMut for Unused {
    fn visit_item_fn_mut(&mut self, f: &mut syn::ItemFn) {
        mark(&mut f.sig, &mut f.block);
        syn::visit_mut::visit_item_fn_mut(self, f);
    }
    fn visit_impl_item_fn_mut(&mut self, f: &mut syn::ImplItemFn) {
        mark(&mut f.sig, &mut f.block);
        syn::visit_mut::visit_impl_item_fn_mut(self, f);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use quote::quote;

    #[test]
    fn renames_only_what_the_body_never_names() {
        let mut file: syn::File = syn::parse2(quote! {
            fn f(x: &[f64; 1], q: &[f64; 2], tp: u8) -> f64 { q[0] + g(|| x[0]) }
            impl S { fn m(&self, a: u8, mut b: u8) -> u8 { a } }
            fn h(fixed: F) -> u8 { let F { x, y, z } = fixed; y + 1 }
            fn t((x, xd): (u8, u8), y: u8) -> u8 { xd + y }
        })
        .unwrap();
        Unused.visit_file_mut(&mut file);
        let text = prettyplease::unparse(&file);
        assert!(
            text.contains("fn f(x: &[f64; 1], q: &[f64; 2], _tp: u8)"),
            "{text}"
        );
        assert!(text.contains("fn m(&self, a: u8, _b: u8)"), "{text}");
        assert!(text.contains("let F { y, .. } = fixed;"), "{text}");
        assert!(text.contains("fn t((_x, xd): (u8, u8), y: u8)"), "{text}");
    }
}
