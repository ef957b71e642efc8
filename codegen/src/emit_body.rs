//! Stage 6a: straight-line code for a set of DAG roots. Every reachable node becomes one
//! `let tN = …;` in DAG order (children first, so CSE is already done); a sine and cosine of one
//! argument become one `sin_cos()` call; constants and variables are written inline.

use std::collections::HashMap;

use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};

use crate::dag::{Dag, Node, NodeId, Var};

/// How variables are read inside an emitted function.
pub trait VarSource {
    /// The local name a variable is bound to, and the expression that reads it from the arguments.
    fn bind(&self, v: Var) -> (Ident, TokenStream);
    /// An expression giving `(sin v, cos v)` without computing them (a cache), if there is one.
    fn trig(&self, v: Var) -> Option<TokenStream> {
        let _ = v;
        None
    }
}

/// Statements computing `roots`, and the expression (an identifier or a literal) of each root.
pub struct Body {
    pub stmts: TokenStream,
    pub roots: Vec<TokenStream>,
}

/// Emits the code for `roots`. Only nodes reachable from them are computed.
pub fn body(dag: &Dag, roots: &[NodeId], vars: &dyn VarSource) -> Body {
    let n = roots.iter().map(|r| r.index() + 1).max().unwrap_or(0);
    let mut live = vec![false; n];
    let mut stack: Vec<NodeId> = roots.to_vec();
    while let Some(id) = stack.pop() {
        if !std::mem::replace(&mut live[id.index()], true) {
            stack.extend(dag.node(id).children());
        }
    }
    // Sine and cosine of the same argument, both live: one sin_cos.
    let mut sin_of: HashMap<NodeId, NodeId> = HashMap::new();
    let mut cos_of: HashMap<NodeId, NodeId> = HashMap::new();
    for (i, node) in dag.nodes()[..n].iter().enumerate() {
        if !live[i] {
            continue;
        }
        match *node {
            Node::Sin(a) => {
                sin_of.insert(a, NodeId(i as u32));
            }
            Node::Cos(a) => {
                cos_of.insert(a, NodeId(i as u32));
            }
            _ => {}
        }
    }

    let mut names: Vec<Option<TokenStream>> = vec![None; n];
    let mut stmts = TokenStream::new();
    let mut var_binds: Vec<(Var, TokenStream)> = Vec::new();
    let mut temp = 0usize;
    for (i, node) in dag.nodes()[..n].iter().enumerate() {
        if !live[i] || names[i].is_some() {
            continue;
        }
        let name = |id: NodeId, names: &[Option<TokenStream>]| {
            names[id.index()].clone().unwrap_or_default()
        };
        let expr = match *node {
            Node::Const(b) => {
                names[i] = Some(literal(f64::from_bits(b)));
                continue;
            }
            Node::Var(v) => {
                let (ident, read) = vars.bind(v);
                var_binds.push((v, quote!(let #ident = #read;)));
                names[i] = Some(quote!(#ident));
                continue;
            }
            Node::Sin(a) | Node::Cos(a) if matches!(dag.node(a), Node::Var(v) if vars.trig(v).is_some()) =>
            {
                let Node::Var(v) = dag.node(a) else { continue };
                let (ident, _) = vars.bind(v);
                let (sn, cn) = (format_ident!("s_{}", ident), format_ident!("c_{}", ident));
                let src = vars.trig(v).unwrap_or_default();
                stmts.extend(quote!(let (#sn, #cn) = #src;));
                if let Some(s) = sin_of.get(&a) {
                    names[s.index()] = Some(quote!(#sn));
                }
                if let Some(c) = cos_of.get(&a) {
                    names[c.index()] = Some(quote!(#cn));
                }
                continue;
            }
            Node::Sin(a) | Node::Cos(a) if sin_of.contains_key(&a) && cos_of.contains_key(&a) => {
                let (s, c) = (sin_of[&a], cos_of[&a]);
                let (sn, cn) = match dag.node(a) {
                    Node::Var(v) => {
                        let (ident, _) = vars.bind(v);
                        (format_ident!("s_{}", ident), format_ident!("c_{}", ident))
                    }
                    _ => (format_ident!("s{}", temp), format_ident!("c{}", temp)),
                };
                temp += 1;
                let arg = name(a, &names);
                stmts.extend(quote!(let (#sn, #cn) = #arg.sin_cos();));
                names[s.index()] = Some(quote!(#sn));
                names[c.index()] = Some(quote!(#cn));
                continue;
            }
            Node::Add(a, b) => {
                let (a, b) = (name(a, &names), name(b, &names));
                quote!(#a + #b)
            }
            Node::Sub(a, b) => {
                let (a, b) = (name(a, &names), name(b, &names));
                quote!(#a - #b)
            }
            Node::Mul(a, b) => {
                let (a, b) = (name(a, &names), name(b, &names));
                quote!(#a * #b)
            }
            Node::Div(a, b) => {
                let (a, b) = (name(a, &names), name(b, &names));
                quote!(#a / #b)
            }
            Node::Neg(a) => {
                let a = name(a, &names);
                quote!(-#a)
            }
            Node::Sin(a) => {
                let a = name(a, &names);
                quote!(#a.sin())
            }
            Node::Cos(a) => {
                let a = name(a, &names);
                quote!(#a.cos())
            }
            Node::Tan(a) => {
                let a = name(a, &names);
                quote!(#a.tan())
            }
            Node::Sqrt(a) => {
                let a = name(a, &names);
                quote!(#a.sqrt())
            }
        };
        let t = format_ident!("t{}", temp);
        temp += 1;
        stmts.extend(quote!(let #t = #expr;));
        names[i] = Some(quote!(#t));
    }
    var_binds.sort_by_key(|(v, _)| *v);
    let mut all: TokenStream = var_binds.into_iter().map(|(_, s)| s).collect();
    all.extend(stmts);
    let roots = roots
        .iter()
        .map(|r| names[r.index()].clone().unwrap_or_default())
        .collect();
    Body { stmts: all, roots }
}

/// A constant in generic scalar code.
pub fn literal(x: f64) -> TokenStream {
    if x == 0.0 {
        return quote!(T::zero());
    }
    if x == 1.0 {
        return quote!(T::one());
    }
    let lit = Literal::f64_unsuffixed(x.abs());
    if x < 0.0 {
        quote!(T::lit(-#lit))
    } else {
        quote!(T::lit(#lit))
    }
}
