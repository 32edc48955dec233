//! Parameters named in messages, spelled by each front end its own way.
//!
//! A library error that tells the user to change a parameter names it with
//! [`param`] (`⟨max_memory⟩`) or [`param_value`] (`⟨boundary=cyclic⟩`), the
//! parameter's field name in the engine's job schema. Each front end renders
//! the message with [`spell`]: the CLI as its flags (`--max-memory`,
//! `--boundary cyclic`), Python as keywords (`max_memory=`, `boundary="cyclic"`),
//! so no library message carries one front end's wording. A marker may be
//! written straight into a string literal (`"raise ⟨size⟩"`). Text without
//! markers, and angle brackets around anything but a snake_case name (the
//! mean ⟨W²⟩ of physics), are left as they are.

/// How a front end writes a parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Spelling {
    /// `--kebab-case` flags (`--max-memory`, `--boundary cyclic`).
    Cli,
    /// Python keywords (`max_memory=`, `boundary="cyclic"`).
    Python,
    /// The schema's field names as they are (`max_memory`, `boundary = cyclic`).
    Plain,
}

const OPEN: char = '⟨';
const CLOSE: char = '⟩';

/// The parameter `name` (a schema field name, snake_case) in a message.
pub fn param(name: &str) -> String {
    format!("{OPEN}{name}{CLOSE}")
}

/// The parameter `name` set to `value` in a message (`--boundary cyclic`).
pub fn param_value(name: &str, value: impl std::fmt::Display) -> String {
    format!("{OPEN}{name}={value}{CLOSE}")
}

/// `text` with every parameter marker written as `spelling` says.
pub fn spell(text: &str, spelling: Spelling) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(start) = rest.find(OPEN) {
        let after = &rest[start + OPEN.len_utf8()..];
        let Some(end) = after.find(CLOSE) else { break };
        let (name, value) = match after[..end].split_once('=') {
            Some((n, v)) => (n, Some(v)),
            None => (&after[..end], None),
        };
        if !is_name(name) {
            // an angle bracket of mathematics, ⟨W²⟩: kept as it is
            out.push_str(&rest[..start + OPEN.len_utf8()]);
            rest = after;
            continue;
        }
        out.push_str(&rest[..start]);
        out.push_str(&spelled(name, value, spelling));
        rest = &after[end + CLOSE.len_utf8()..];
    }
    out.push_str(rest);
    out
}

fn spelled(name: &str, value: Option<&str>, spelling: Spelling) -> String {
    match (spelling, value) {
        (Spelling::Cli, None) => format!("--{}", name.replace('_', "-")),
        (Spelling::Cli, Some(v)) => format!("--{} {v}", name.replace('_', "-")),
        (Spelling::Python, None) => format!("{name}="),
        (Spelling::Python, Some(v)) if is_number(v) => format!("{name}={v}"),
        (Spelling::Python, Some(v)) => format!("{name}={v:?}"),
        (Spelling::Plain, None) => name.to_owned(),
        (Spelling::Plain, Some(v)) => format!("{name} = {v}"),
    }
}

/// A schema field name: `snake_case` ASCII.
fn is_name(s: &str) -> bool {
    s.starts_with(|c: char| c.is_ascii_lowercase())
        && s.bytes()
            .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'_')
}

fn is_number(v: &str) -> bool {
    v.parse::<f64>().is_ok() || matches!(v, "True" | "False" | "None")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_front_end_spells_the_parameters_its_way() {
        let msg = format!(
            "the grid would need 3 GiB (raise it with {}); {} has no region: drop {}",
            param("max_memory"),
            param_value("boundary", "infinite"),
            param("size")
        );
        assert_eq!(
            spell(&msg, Spelling::Cli),
            "the grid would need 3 GiB (raise it with --max-memory); --boundary infinite has no region: drop --size"
        );
        assert_eq!(
            spell(&msg, Spelling::Python),
            "the grid would need 3 GiB (raise it with max_memory=); boundary=\"infinite\" has no region: drop size="
        );
        assert_eq!(
            spell(&msg, Spelling::Plain),
            "the grid would need 3 GiB (raise it with max_memory); boundary = infinite has no region: drop size"
        );
        assert_eq!(spell(&param_value("runs", 3), Spelling::Python), "runs=3");
    }

    #[test]
    fn text_without_markers_or_with_brackets_of_mathematics_is_kept() {
        for t in [
            "plain text",
            "a ⟨ alone",
            "⟩ first ⟨x",
            "",
            "H(τ) = ⟨(z(x+τ) − z(x))²⟩",
            "⟨W²⟩ = t",
        ] {
            assert_eq!(spell(t, Spelling::Cli), t);
        }
    }
}
