//! Stage 6a: straight-line code for a set of DAG roots. Every reachable node becomes one
//! `let tN = …;` in DAG order (children first, so CSE is already done); a sine and cosine of one
//! argument become one `sin_cos()` call; constants and variables are written inline.

use std::collections::HashMap;

use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};

use crate::emit::names::{Local, Names};
use crate::ir::dag::{Dag, Node, NodeId, Var};

/// How variables are read inside an emitted function.
pub trait VarSource {
    /// The expression that reads a variable from the arguments.
    fn read(&self, v: Var) -> TokenStream;
    /// A readable name for the local a variable is bound to (the names table makes it unique).
    fn hint(&self, v: Var) -> String;
    /// An expression giving `(sin v, cos v)` without computing them (a cache), if there is one.
    fn trig(&self, v: Var) -> Option<TokenStream> {
        let _ = v;
        None
    }
    /// The scalar type parameter of the generated code (`T`).
    fn scalar(&self) -> &Ident;
}

/// Locals the emitters write themselves (arguments and fixed bindings of the generated
/// functions): the names table never gives them to a node.
pub const FIXED_LOCALS: &[&str] = &[
    "a",
    "every_angle",
    "guess",
    "jac",
    "keep",
    "kx",
    "ky",
    "lu",
    "m",
    "o",
    "ok",
    "options",
    "p",
    "pa",
    "pivot",
    "params",
    "pb",
    "points",
    "q",
    "qd",
    "qdd",
    "ra",
    "rb",
    "report",
    "s",
    "same",
    "fresh_tp",
    "st",
    "t",
    "tolerance",
    "tp",
    "tq",
    "tx",
    "v",
    "x",
    "xd",
    "xdd",
    "z",
];
/// Statements computing `roots`, and the expression (an identifier or a literal) of each root.
pub struct Body {
    pub stmts: TokenStream,
    pub roots: Vec<TokenStream>,
}

/// Emits the code for `roots`. Only nodes reachable from them are computed.
pub fn body(dag: &Dag, roots: &[NodeId], vars: &dyn VarSource) -> Body {
    Builder::new(dag, vars).segment(roots)
}

/// Straight-line code in segments that share one scope: a node computed by an earlier segment
/// is reused by name, not recomputed (CSE across the segments of one function). Between
/// segments the caller emits its own statements (a block solve), which may write the arrays
/// later segments read: a variable is bound where it is first used.
pub struct Builder<'a> {
    dag: &'a Dag,
    vars: &'a dyn VarSource,
    names: Vec<Option<TokenStream>>,
    locals: Names<Local>,
    temp: usize,
}

impl<'a> Builder<'a> {
    pub fn new(dag: &'a Dag, vars: &'a dyn VarSource) -> Self {
        Builder {
            dag,
            vars,
            names: vec![None; dag.nodes().len()],
            locals: Names::new(FIXED_LOCALS.iter().copied()),
            temp: 0,
        }
    }

    /// The statements computing `roots` that earlier segments did not, and each root's
    /// expression.
    pub fn segment(&mut self, roots: &[NodeId]) -> Body {
        let (dag, vars) = (self.dag, self.vars);
        let n = roots.iter().map(|r| r.index() + 1).max().unwrap_or(0);
        let mut live = vec![false; n];
        let mut stack: Vec<NodeId> = roots.to_vec();
        while let Some(id) = stack.pop() {
            if self.names[id.index()].is_none() && !std::mem::replace(&mut live[id.index()], true) {
                // A sine or cosine read from a cache does not need its variable's value.
                match dag.node(id) {
                    Node::Sin(a) | Node::Cos(a) if matches!(dag.node(a), Node::Var(v) if vars.trig(v).is_some()) =>
                        {}
                    node => stack.extend(node.children()),
                }
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

        let mut stmts = TokenStream::new();
        let mut var_binds: Vec<(Var, TokenStream)> = Vec::new();
        for (i, node) in dag.nodes()[..n].iter().enumerate() {
            if !live[i] || self.names[i].is_some() {
                continue;
            }
            let name = |id: NodeId, names: &[Option<TokenStream>]| {
                names[id.index()].clone().unwrap_or_default()
            };
            let expr = match *node {
                Node::Const(b) => {
                    self.names[i] = Some(literal(f64::from_bits(b), vars.scalar()));
                    continue;
                }
                Node::Var(v) => {
                    let ident = self.locals.get(Local::Value(v), &[&vars.hint(v)]);
                    let read = vars.read(v);
                    var_binds.push((v, quote!(let #ident = #read;)));
                    self.names[i] = Some(quote!(#ident));
                    continue;
                }
                Node::Sin(a) | Node::Cos(a) if matches!(dag.node(a), Node::Var(v) if vars.trig(v).is_some()) =>
                {
                    let Node::Var(v) = dag.node(a) else { continue };
                    let (sn, cn) = self.trig_names(v);
                    let src = vars.trig(v).unwrap_or_default();
                    // Only what this segment reads is bound; a later segment that needs the
                    // other one binds it from the same cache.
                    let (s, c) = (dag.find(&Node::Sin(a)), dag.find(&Node::Cos(a)));
                    let wanted =
                        |id: Option<NodeId>| id.filter(|id| id.index() < n && live[id.index()]);
                    let (s, c) = (wanted(s), wanted(c));
                    let pat_s = if s.is_some() { quote!(#sn) } else { quote!(_) };
                    let pat_c = if c.is_some() { quote!(#cn) } else { quote!(_) };
                    stmts.extend(quote!(let (#pat_s, #pat_c) = #src;));
                    for (id, nm) in [(s, &sn), (c, &cn)] {
                        if let Some(id) = id {
                            self.names[id.index()] = Some(quote!(#nm));
                        }
                    }
                    continue;
                }
                Node::Sin(a) | Node::Cos(a)
                    if sin_of.contains_key(&a) && cos_of.contains_key(&a) =>
                {
                    let (s, c) = (sin_of[&a], cos_of[&a]);
                    let (sn, cn) = match dag.node(a) {
                        Node::Var(v) => self.trig_names(v),
                        _ => {
                            let n = self.temp;
                            (
                                self.locals.get(Local::TempSin(n), &[&format!("s{n}")]),
                                self.locals.get(Local::TempCos(n), &[&format!("c{n}")]),
                            )
                        }
                    };
                    self.temp += 1;
                    let arg = name(a, &self.names);
                    stmts.extend(quote!(let (#sn, #cn) = #arg.sin_cos();));
                    self.names[s.index()] = Some(quote!(#sn));
                    self.names[c.index()] = Some(quote!(#cn));
                    continue;
                }
                Node::Add(a, b) => {
                    let (a, b) = (name(a, &self.names), name(b, &self.names));
                    quote!(#a + #b)
                }
                Node::Sub(a, b) => {
                    let (a, b) = (name(a, &self.names), name(b, &self.names));
                    quote!(#a - #b)
                }
                Node::Mul(a, b) => {
                    let (a, b) = (name(a, &self.names), name(b, &self.names));
                    quote!(#a * #b)
                }
                Node::Div(a, b) => {
                    let (a, b) = (name(a, &self.names), name(b, &self.names));
                    quote!(#a / #b)
                }
                Node::Neg(a) => {
                    let a = name(a, &self.names);
                    quote!(-#a)
                }
                Node::Sin(a) => {
                    let a = name(a, &self.names);
                    quote!(#a.sin())
                }
                Node::Cos(a) => {
                    let a = name(a, &self.names);
                    quote!(#a.cos())
                }
                Node::Tan(a) => {
                    let a = name(a, &self.names);
                    quote!(#a.tan())
                }
                Node::Sqrt(a) => {
                    let a = name(a, &self.names);
                    quote!(#a.sqrt())
                }
                Node::Func(f, a, b) => {
                    let method = format_ident!("{}", f.method());
                    let a = name(a, &self.names);
                    if f.arity() == 2 {
                        let b = name(b, &self.names);
                        quote!(#a.#method(#b))
                    } else {
                        quote!(#a.#method())
                    }
                }
            };
            let n = self.temp;
            let t = self.locals.get(Local::Temp(n), &[&format!("t{n}")]);
            self.temp += 1;
            stmts.extend(quote!(let #t = #expr;));
            self.names[i] = Some(quote!(#t));
        }
        var_binds.sort_by_key(|(v, _)| *v);
        let mut all: TokenStream = var_binds.into_iter().map(|(_, s)| s).collect();
        all.extend(stmts);
        let roots = roots
            .iter()
            .map(|r| self.names[r.index()].clone().unwrap_or_default())
            .collect();
        Body { stmts: all, roots }
    }

    /// The locals of a variable's sine and cosine: `s_`/`c_` and the variable's own local.
    fn trig_names(&mut self, v: Var) -> (Ident, Ident) {
        let ident = self.locals.get(Local::Value(v), &[&self.vars.hint(v)]);
        (
            self.locals.get(Local::Sin(v), &[&format!("s_{ident}")]),
            self.locals.get(Local::Cos(v), &[&format!("c_{ident}")]),
        )
    }
}

/// A constant in generic scalar code (`gt`: the scalar type parameter).
pub fn literal(x: f64, gt: &Ident) -> TokenStream {
    if x == 0.0 {
        return quote!(#gt::zero());
    }
    if x == 1.0 {
        return quote!(#gt::one());
    }
    let lit = Literal::f64_unsuffixed(x.abs());
    if x < 0.0 {
        quote!(#gt::lit(-#lit))
    } else {
        quote!(#gt::lit(#lit))
    }
}
