//! Stage 6, comments in generated code: tokens have no comments, so an emitter writes a
//! `__comment!("…");` marker statement ([`comment`]) where a `// …` line belongs, and after
//! `prettyplease` has printed the file, [`markers_to_comments`] turns every marker (on one line,
//! or spread over several when prettyplease splits a long literal) into `// …` lines at its
//! indentation. Comment text is wrapped at [`COMMENT_WIDTH`] characters.

use proc_macro2::TokenStream;
use quote::quote;

/// Characters per generated comment line.
pub(crate) const COMMENT_WIDTH: usize = 80;

/// `// text` in the generated code, as `__comment!` markers, one per line of at most
/// [`COMMENT_WIDTH`] characters (split at spaces; a longer word keeps its own line).
pub(crate) fn comment(text: &str) -> TokenStream {
    wrap(text, COMMENT_WIDTH)
        .iter()
        .map(|line| quote!(__comment!(#line);))
        .collect()
}

/// Appends `pretty` (printed code) to `out` with every `__comment!("…");` marker turned into a
/// `// …` line; an error only if a marker's literal does not parse (a generator bug).
pub(crate) fn markers_to_comments(pretty: &str, out: &mut String) -> Result<(), String> {
    let mut lines = pretty.lines();
    while let Some(line) = lines.next() {
        let t = line.trim_start();
        let indent = &line[..line.len() - t.len()];
        let Some(rest) = t.strip_prefix("__comment!(") else {
            out.push_str(line);
            out.push('\n');
            continue;
        };
        // `__comment!("…");` on one line, or, when the text is too long for one, the literal on
        // the lines up to `);`.
        let literal = match rest.strip_suffix(");") {
            Some(lit) => lit.to_string(),
            None => lines
                .by_ref()
                .map(str::trim)
                .take_while(|l| *l != ");")
                .collect::<String>(),
        };
        let literal = literal.trim_end_matches(',');
        let text = syn::parse_str::<syn::LitStr>(literal)
            .map_err(|e| format!("internal error: a generated comment does not parse: {e}"))?
            .value();
        out.push_str(indent);
        out.push_str("// ");
        out.push_str(&text);
        out.push('\n');
    }
    Ok(())
}

/// `text` in lines of at most `width` characters, split at spaces.
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split(' ').filter(|w| !w.is_empty()) {
        match lines.last_mut() {
            Some(line) if line.chars().count() + 1 + word.chars().count() <= width => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::{comment, markers_to_comments, wrap};

    #[test]
    fn comments_wrap_at_spaces_and_keep_long_words_whole() {
        assert_eq!(wrap("a bb ccc", 4), ["a bb", "ccc"]);
        assert_eq!(wrap("short", 80), ["short"]);
        let long = "x".repeat(120);
        assert_eq!(wrap(&format!("Scene {long}: blocks [0]."), 80).len(), 3);
        assert!(wrap("", 80).is_empty());
    }

    /// Markers become comments at their indentation, through prettyplease as the emitter runs
    /// it: a short one on its line, a long literal that prettyplease splits over lines, quotes
    /// and backslashes kept; other lines untouched.
    #[test]
    fn markers_become_comment_lines() {
        let long = format!("J[0][1] = ∂Φ0/∂q2 {}", "y".repeat(90));
        let c1 = comment("a \"quoted\" \\ text");
        let c2 = comment(&long);
        let tokens = quote::quote! {
            fn f(x: f64) -> f64 {
                #c1
                let t = x;
                #c2
                t
            }
        };
        let file: syn::File = syn::parse2(tokens).expect("parses");
        let pretty = prettyplease::unparse(&file);
        let mut out = String::new();
        markers_to_comments(&pretty, &mut out).expect("markers parse");
        assert!(!out.contains("__comment"), "{out}");
        assert!(
            out.contains("    // a \"quoted\" \\ text\n    let t = x;\n"),
            "{out}"
        );
        assert!(out.contains("    // J[0][1] = ∂Φ0/∂q2\n"), "{out}");
        assert!(
            out.contains(&format!("    // {}\n", "y".repeat(90))),
            "{out}"
        );
        assert!(out.starts_with("fn f(x: f64) -> f64 {\n"), "{out}");
        let mut bad = String::new();
        assert!(markers_to_comments("__comment!(not a literal);", &mut bad).is_err());
    }
}
