//! Stage 1 (front end): the mechanism file's text → [`ast::File`], with every node's byte span in
//! the file. TOML through toml's span-keeping `DeTable`, expression strings through `syn`.

pub mod ast;
pub mod parse;
mod parse_expr;
