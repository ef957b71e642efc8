//! "Did you mean": the nearest of a list of known keys or names to a misspelt one, by edit
//! distance with transpositions (`unknwons` is one edit from `unknowns`). Used by the front end
//! (keys) and semantics (names).

/// The candidate nearest `name`, when it is close enough to be a likely misspelling: at most one
/// edit for names of up to four characters, two up to eight, three beyond; `None` when several
/// are equally near (`lx` among `l1`, `l2`: no guess is better than a wrong one); never `name`.
pub fn nearest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let limit = match name.chars().count() {
        0..=4 => 1,
        5..=8 => 2,
        _ => 3,
    };
    let mut best: Option<(usize, &str)> = None;
    let mut tied = false;
    for c in candidates {
        let d = distance(name, c);
        if c == name || d > limit {
            continue;
        }
        match best {
            Some((b, other)) if d == b && other != c => tied = true,
            Some((b, _)) if d >= b => {}
            _ => (best, tied) = (Some((d, c)), false),
        }
    }
    best.filter(|_| !tied).map(|(_, c)| c)
}

/// Optimal string alignment distance: insertions, deletions, substitutions and transpositions of
/// two neighbours, by characters.
fn distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let w = b.len() + 1;
    let mut d = vec![0usize; (a.len() + 1) * w];
    for i in 0..=a.len() {
        d[i * w] = i;
    }
    for (j, cell) in d.iter_mut().enumerate().take(w) {
        *cell = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut v = (d[(i - 1) * w + j] + 1)
                .min(d[i * w + j - 1] + 1)
                .min(d[(i - 1) * w + j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                v = v.min(d[(i - 2) * w + j - 2] + 1);
            }
            d[i * w + j] = v;
        }
    }
    d[a.len() * w + b.len()]
}

#[cfg(test)]
mod tests {
    use super::{distance, nearest};

    #[test]
    fn distances_and_suggestions() {
        assert_eq!(distance("unknwons", "unknowns"), 1);
        assert_eq!(distance("", "abc"), 3);
        assert_eq!(distance("kitten", "sitting"), 3);
        let keys = [
            "description",
            "inputs",
            "unknowns",
            "loops",
            "params",
            "points",
            "start",
        ];
        assert_eq!(nearest("unknwons", keys), Some("unknowns"));
        assert_eq!(nearest("loop", keys), Some("loops"));
        assert_eq!(nearest("param", keys), Some("params"));
        assert_eq!(nearest("strat", keys), Some("start"));
        assert_eq!(nearest("colour", keys), None);
        assert_eq!(nearest("l3", ["l1", "l2", "q3"]), None);
        assert_eq!(nearest("lenght", ["length", "width"]), Some("length"));
        assert_eq!(nearest("xyz", ["l1", "l2"]), None);
        assert_eq!(nearest("start", keys), None);
    }
}
