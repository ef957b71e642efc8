//! Each quantity is computed once per generated function, sign included (issue 17 item 7): the
//! default file's generated code (the golden `generated/mechanisms.rs`) is parsed, and within each
//! function no `let` recomputes an arithmetic expression that a `let` visible from it (same block
//! or an enclosing one) already computes, up to sign and to the order of the operands of `+` and
//! `*` (so `t10 - t11` after `t11 - t10`, or `-t9 - t8` after `t8 + t9`, is an error).

use std::collections::HashMap;

use syn::{BinOp, Block, Expr, ImplItem, Item, Pat, Stmt, UnOp};

/// An expression up to sign: `(negated, canonical text)`; `None` for what is not arithmetic.
fn canonical(e: &Expr) -> (bool, String) {
    match e {
        Expr::Paren(p) => canonical(&p.expr),
        Expr::Unary(u) if matches!(u.op, UnOp::Neg(_)) => {
            let (s, c) = canonical(&u.expr);
            (!s, c)
        }
        Expr::Binary(b) => match b.op {
            BinOp::Add(_) | BinOp::Sub(_) => {
                let mut terms = Vec::new();
                sum_terms(e, false, &mut terms);
                terms.sort_by(|a, b| a.1.cmp(&b.1).then(a.0.cmp(&b.0)));
                let flip = terms.first().is_some_and(|t| t.0);
                let text: Vec<String> = terms
                    .iter()
                    .map(|(s, c)| format!("{}{c}", if *s != flip { "-" } else { "+" }))
                    .collect();
                (flip, format!("sum({})", text.join(" ")))
            }
            BinOp::Mul(_) => {
                let (sa, ca) = canonical(&b.left);
                let (sb, cb) = canonical(&b.right);
                let mut f = [ca, cb];
                f.sort();
                (sa != sb, format!("mul({}, {})", f[0], f[1]))
            }
            BinOp::Div(_) => {
                let (sa, ca) = canonical(&b.left);
                let (sb, cb) = canonical(&b.right);
                (sa != sb, format!("div({ca}, {cb})"))
            }
            _ => (false, quote::quote!(#e).to_string()),
        },
        _ => (false, quote::quote!(#e).to_string()),
    }
}

/// The signed terms of a sum or difference.
fn sum_terms(e: &Expr, neg: bool, out: &mut Vec<(bool, String)>) {
    match e {
        Expr::Paren(p) => sum_terms(&p.expr, neg, out),
        Expr::Unary(u) if matches!(u.op, UnOp::Neg(_)) => sum_terms(&u.expr, !neg, out),
        Expr::Binary(b) if matches!(b.op, BinOp::Add(_) | BinOp::Sub(_)) => {
            sum_terms(&b.left, neg, out);
            sum_terms(&b.right, neg != matches!(b.op, BinOp::Sub(_)), out);
        }
        _ => {
            let (s, c) = canonical(e);
            out.push((s != neg, c));
        }
    }
}

/// Whether a `let`'s value is arithmetic worth comparing (not a plain name, literal or index).
fn arithmetic(e: &Expr) -> bool {
    match e {
        Expr::Paren(p) => arithmetic(&p.expr),
        Expr::Binary(b) => matches!(
            b.op,
            BinOp::Add(_) | BinOp::Sub(_) | BinOp::Mul(_) | BinOp::Div(_)
        ),
        Expr::Unary(u) => matches!(u.op, UnOp::Neg(_)) && arithmetic(&u.expr),
        _ => false,
    }
}

struct Check<'a> {
    function: String,
    found: &'a mut Vec<String>,
}

impl Check<'_> {
    /// The `let`s of `block` against those of the enclosing scopes (`outer`).
    fn block(&mut self, block: &Block, outer: &HashMap<String, (String, bool)>) {
        let mut scope = outer.clone();
        for stmt in &block.stmts {
            match stmt {
                Stmt::Local(local) => {
                    let Some(init) = &local.init else { continue };
                    self.expr(&init.expr, &scope);
                    if !arithmetic(&init.expr) {
                        continue;
                    }
                    let name = match &local.pat {
                        Pat::Ident(i) => i.ident.to_string(),
                        p => quote::quote!(#p).to_string(),
                    };
                    let (sign, key) = canonical(&init.expr);
                    if let Some((first, first_sign)) = scope.get(&key) {
                        self.found.push(format!(
                            "{}: `{name}` recomputes `{first}` ({}): {key}",
                            self.function,
                            if *first_sign == sign {
                                "same sign"
                            } else {
                                "opposite sign"
                            }
                        ));
                    } else {
                        scope.insert(key, (name, sign));
                    }
                }
                Stmt::Expr(e, _) => self.expr(e, &scope),
                _ => {}
            }
        }
    }

    /// Blocks nested in an expression (branches, loops, closures) see the enclosing lets.
    fn expr(&mut self, e: &Expr, scope: &HashMap<String, (String, bool)>) {
        match e {
            Expr::Block(b) => self.block(&b.block, scope),
            Expr::If(i) => {
                self.block(&i.then_branch, scope);
                if let Some((_, e)) = &i.else_branch {
                    self.expr(e, scope);
                }
            }
            Expr::Match(m) => m.arms.iter().for_each(|a| self.expr(&a.body, scope)),
            Expr::ForLoop(f) => self.block(&f.body, scope),
            Expr::While(w) => self.block(&w.body, scope),
            Expr::Loop(l) => self.block(&l.body, scope),
            Expr::Closure(c) => self.expr(&c.body, scope),
            _ => {}
        }
    }
}

fn items(items: &[Item], path: &str, found: &mut Vec<String>) -> usize {
    let mut functions = 0;
    for item in items {
        match item {
            Item::Mod(m) => {
                if let Some((_, inner)) = &m.content {
                    functions += self::items(inner, &format!("{path}{}::", m.ident), found);
                }
            }
            Item::Fn(f) => {
                functions += 1;
                let function = format!("{path}{}", f.sig.ident);
                Check { function, found }.block(&f.block, &HashMap::new());
            }
            Item::Impl(i) => {
                for it in &i.items {
                    if let ImplItem::Fn(f) = it {
                        functions += 1;
                        let function = format!("{path}{}", f.sig.ident);
                        Check { function, found }.block(&f.block, &HashMap::new());
                    }
                }
            }
            _ => {}
        }
    }
    functions
}

fn duplicates(code: &str) -> (usize, Vec<String>) {
    let file = syn::parse_file(code).expect("generated code parses");
    let mut found = Vec::new();
    let functions = items(&file.items, "", &mut found);
    (functions, found)
}

#[test]
fn each_quantity_once_per_function_sign_included() {
    let code = include_str!("../../generated/mechanisms.rs");
    let (functions, found) = duplicates(code);
    assert!(functions > 100, "{functions} functions read");
    assert!(
        found.is_empty(),
        "{} duplicate(s):\n{}",
        found.len(),
        found.join("\n")
    );
}

/// The checker itself finds what it is for.
#[test]
fn the_checker_finds_a_quantity_twice_up_to_sign() {
    let code = "fn f(a: f64, b: f64, c: f64) -> f64 {
        let t1 = a - b; let t2 = a + c; let t3 = a * b;
        let t4 = b - a; let t5 = -c - a; let t6 = b * a; let t7 = -(a * b);
        if c > 0.0 { let t8 = a - b; t8 } else { let t9 = c * a; t9 }
    }";
    let (_, found) = duplicates(code);
    let names: Vec<&str> = found.iter().map(|f| f.split('`').nth(1).unwrap()).collect();
    assert_eq!(names, ["t4", "t5", "t6", "t7", "t8"], "{found:#?}");
    let (_, none) = duplicates(
        "fn g(a: f64, b: f64) -> f64 { let t1 = a - b; let t2 = a / b; let t3 = b / a; t1 + t2 + t3 }",
    );
    assert!(none.is_empty(), "{none:?}");
}
