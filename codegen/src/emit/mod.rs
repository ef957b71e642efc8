//! Stage 6 (emit): compiled mechanisms → one Rust source file: the file-level items (`MECHANISMS`,
//! `lookup`, `visit_all`) and one module per mechanism ([`crate::emit::module`]), built with `quote`,
//! parsed into a `syn::File`, normalized on the syntax tree ([`Tidy`]: integer literals without
//! their `usize` suffix, doc text after a space) and printed by `prettyplease`;
//! `__comment!("…");` marker statements then become `// …` lines. Output is deterministic.

use proc_macro2::TokenStream;
use quote::{format_ident, quote};

mod args;
mod bodies;
mod body;
mod cache;
mod closed;
mod comments;
mod lane_items;
mod lanes;
mod module;
mod motion;
pub(crate) mod names;
mod scene;
mod sensitivity;
mod solve;
mod system;
mod twofold;
mod unused;

use crate::analysis::Compiled;

/// An id is written as its index, an unsuffixed integer (`qd[3]`, `blocks: &[0, 1]`).
macro_rules! index_tokens {
    ($($id:ty),*) => {$(
        impl quote::ToTokens for $id {
            fn to_tokens(&self, tokens: &mut TokenStream) {
                tokens.extend([proc_macro2::TokenTree::Literal(
                    proc_macro2::Literal::usize_unsuffixed(self.index()),
                )]);
            }
        }
    )*};
}
index_tokens!(
    crate::sema::resolved::UnknownId,
    crate::analysis::structure::BlockId
);
pub use args::type_ident;
use names::ModuleItems;

/// The runtime path generated code uses unless told otherwise: users depend on `mechgen`.
pub const DEFAULT_RUNTIME: &str = "::mechgen";

/// The whole generated file, reaching the runtime through `runtime` (a path such as `::mechgen`
/// or `::mechgen_runtime`): every runtime item is named `{runtime}::__private::…`.
pub fn emit_with(mechs: &[Compiled], source_name: &str, runtime: &str) -> Result<String, String> {
    let path: syn::Path = syn::parse_str(runtime)
        .map_err(|e| format!("the runtime path `{runtime}` is not a Rust path: {e}"))?;
    let rt = quote!(#path::__private);
    let gt = format_ident!("T");
    let modules: Vec<TokenStream> = mechs
        .iter()
        .map(|c| crate::emit::module::module(c, &rt))
        .collect();
    let names: Vec<&str> = mechs.iter().map(|m| m.model.name.text.as_str()).collect();
    let count = names.len();
    let arms = mechs.iter().map(|m| {
        let name = &m.model.name.text;
        let (module, ty) = (format_ident!("{}", name), type_ident(&m.model));
        quote!(#name => ::core::option::Option::Some(::std::boxed::Box::new(
            <#module::#ty::<#gt> as ::core::default::Default>::default())),)
    });
    // With params: the base params in file order (`Params::to_array`'s), checked for length.
    let param_arms = mechs.iter().map(|m| {
        let name = &m.model.name.text;
        let items = ModuleItems::new(name);
        let (module, ty, params_ty) = (format_ident!("{}", name), &items.ty, &items.params);
        quote!(#name => <[#gt; _]>::try_from(params).ok().map(|a| {
            ::std::boxed::Box::new(#module::#ty::<#gt>::new(#module::#params_ty::from_array(a)))
                as ::std::boxed::Box<dyn #rt::DynMechanism<#gt>>
        }),)
    });
    let visits = mechs.iter().map(|m| {
        let (module, ty) = (format_ident!("{}", m.model.name.text), type_ident(&m.model));
        quote!(v.visit(&<#module::#ty::<#gt> as ::core::default::Default>::default());)
    });
    let scenes = crate::emit::scene::all(mechs);
    let scene_modules = scenes
        .iter()
        .map(|(c, p)| crate::emit::scene::module(c, p, &rt));
    let scene_names: Vec<&str> = scenes.iter().map(|(_, p)| p.name.as_str()).collect();
    let scene_count = scene_names.len();
    let scene_ty = |p: &crate::analysis::scene::ScenePlan| {
        (format_ident!("{}", p.name), ModuleItems::new(&p.name).ty)
    };
    let scene_arms = scenes.iter().map(|(_, p)| {
        let (name, (module, ty)) = (&p.name, scene_ty(p));
        quote!(#name => ::core::option::Option::Some(::std::boxed::Box::new(
            <#module::#ty::<#gt> as ::core::default::Default>::default())),)
    });
    // With params: the scene's mechanism's base params in file order.
    let scene_param_arms = scenes.iter().map(|(_, p)| {
        let (name, (module, ty)) = (&p.name, scene_ty(p));
        quote!(#name => <#module::#ty::<#gt> as #rt::Scene<#gt>>::with_params(params).map(|s| {
            ::std::boxed::Box::new(s) as ::std::boxed::Box<dyn #rt::DynScene<#gt>>
        }),)
    });
    let scene_visits = scenes.iter().map(|(_, p)| {
        let (module, ty) = scene_ty(p);
        quote!(v.visit(&<#module::#ty::<#gt> as ::core::default::Default>::default());)
    });
    // A file without scenes: the same functions, with nothing to match or visit.
    let (scene_match, scene_param_match, visitor) = if scene_count == 0 {
        (
            quote!(let _ = name; ::core::option::Option::None),
            quote!(let _ = (name, params); ::core::option::Option::None),
            quote!(_v),
        )
    } else {
        (
            quote!(match name { #(#scene_arms)* _ => ::core::option::Option::None, }),
            quote!(match name { #(#scene_param_arms)* _ => ::core::option::Option::None, }),
            quote!(v),
        )
    };
    let file = quote! {
        /// Names of the compiled-in mechanisms, in file order.
        pub const MECHANISMS: [&str; #count] = [#(#names),*];

        /// A compiled-in mechanism by name, with its default params, behind the object-safe trait.
        pub fn lookup<#gt: #rt::Real>(name: &str) -> ::core::option::Option<::std::boxed::Box<dyn #rt::DynMechanism<#gt>>> {
            match name {
                #(#arms)*
                _ => ::core::option::Option::None,
            }
        }

        /// A compiled-in mechanism by name with the given base params (file order, as its
        /// `Params::to_array`; derived params follow from them); `None` for an unknown name or a
        /// slice of the wrong length.
        pub fn lookup_with_params<#gt: #rt::Real>(name: &str, params: &[#gt]) -> ::core::option::Option<::std::boxed::Box<dyn #rt::DynMechanism<#gt>>> {
            match name {
                #(#param_arms)*
                _ => ::core::option::Option::None,
            }
        }

        /// Calls `v.visit` with every compiled-in mechanism (default params), statically typed, in
        /// file order: generic code over whatever the build compiled in, without dynamic dispatch.
        pub fn visit_all<#gt: #rt::Real, V: #rt::StaticVisitor<#gt>>(v: &mut V) {
            #(#visits)*
        }

        /// Names of the compiled-in scenes, in file order.
        pub const SCENES: [&str; #scene_count] = [#(#scene_names),*];

        /// A compiled-in scene by name, with its mechanism's default params, behind the object-safe trait.
        pub fn lookup_scene<#gt: #rt::Real>(name: &str) -> ::core::option::Option<::std::boxed::Box<dyn #rt::DynScene<#gt>>> {
            #scene_match
        }

        /// A compiled-in scene by name with its mechanism's base params (file order, as the
        /// mechanism's `Params::to_array`); `None` for an unknown name or a slice of the wrong
        /// length.
        pub fn lookup_scene_with_params<#gt: #rt::Real>(name: &str, params: &[#gt]) -> ::core::option::Option<::std::boxed::Box<dyn #rt::DynScene<#gt>>> {
            #scene_param_match
        }

        /// Calls `v.visit` with every compiled-in scene (default params), statically typed, in file order.
        pub fn visit_scenes<#gt: #rt::Real, V: #rt::SceneVisitor<#gt>>(#visitor: &mut V) {
            #(#scene_visits)*
        }

        #(#modules)*
        #(#scene_modules)*
    };
    let mut parsed: syn::File = syn::parse2(file)
        .map_err(|e| format!("internal error: generated code does not parse: {e}"))?;
    syn::visit_mut::VisitMut::visit_file_mut(&mut Tidy, &mut parsed);
    syn::visit_mut::VisitMut::visit_file_mut(&mut unused::Unused, &mut parsed);
    let pretty = prettyplease::unparse(&parsed);
    let mut out = format!(
        "// @generated by mechgen-codegen {} from {source_name}. Do not edit: edit the mechanism file.\n\n",
        env!("CARGO_PKG_VERSION")
    );
    comments::markers_to_comments(&pretty, &mut out)?;
    Ok(out)
}

/// Normalizes the syntax tree before printing: `quote` writes interpolated integers with their
/// suffix (`3usize` → `3`), and a doc string given as `#[doc = …]` gets the space a `///`
/// comment has.
struct Tidy;

impl syn::visit_mut::VisitMut for Tidy {
    fn visit_lit_int_mut(&mut self, i: &mut syn::LitInt) {
        if i.suffix() == "usize" {
            *i = syn::LitInt::new(i.base10_digits(), i.span());
        }
    }
    fn visit_attribute_mut(&mut self, a: &mut syn::Attribute) {
        if let syn::Meta::NameValue(nv) = &mut a.meta
            && nv.path.is_ident("doc")
            && let syn::Expr::Lit(syn::ExprLit {
                lit: syn::Lit::Str(s),
                ..
            }) = &mut nv.value
        {
            let text = s.value();
            if !text.is_empty() && !text.starts_with(' ') {
                *s = syn::LitStr::new(&format!(" {text}"), s.span());
            }
        }
    }
}
