//! The command line that runs a job with given parameters: what the gallery
//! prints under each picture, and what a Python or Blender user can paste
//! into a shell to make the same bytes again.
//!
//! Made from the parameters and the CLI's own argument definitions (clap's
//! `Args`, derived on each job's struct), never typed by hand: a flag that is
//! renamed, or a value written in a form the CLI no longer reads, fails the
//! round trip test (the line parsed by clap gives the parameters back).

use clap::{ArgAction, Args, Command};
use serde_json::Value;

use super::{DEFAULT_SEED, JobParams, field_names};
use crate::error::{EngineError, Result};

/// A job's parameters with the CLI's flags for them (every job's: the
/// engine derives clap's `Args` on each), for front ends that do not use clap.
pub trait CliJob: JobParams + Args {}

impl<P: JobParams + Args> CliJob for P {}

/// `asperity JOB ARGS… [--seed S] [-o OUTPUT]`: the flags of the fields of
/// `p` that differ from the job's defaults, its positional inputs, and the
/// seed when it is not the default one (seeded jobs only).
///
/// # Errors
/// [`EngineError::Invalid`] for a value the command line cannot say (an
/// unset option whose default is set, a switch turned off).
pub fn command_line<P: CliJob>(p: &P, seed: u64, output: Option<&str>) -> Result<String> {
    let values = as_object(p)?;
    let defaults = as_object(&P::default())?;
    let cmd = P::augment_args(Command::new("asperity"));
    let mut words = vec!["asperity".to_owned(), P::JOB.to_owned()];
    let mut positionals = Vec::new();
    for name in field_names::<P>() {
        let Some(arg) = cmd.get_arguments().find(|a| a.get_id() == name.as_str()) else {
            continue;
        };
        let value = values.get(&name).unwrap_or(&Value::Null);
        if arg.is_positional() {
            if !value.is_null() {
                positionals.push(word(value, arg.get_value_delimiter(), &name)?);
            }
            continue;
        }
        if defaults.get(&name) == Some(value) {
            continue;
        }
        let flag = format!("--{}", arg.get_long().unwrap_or(&name));
        match (value, arg.get_action()) {
            (Value::Bool(true), ArgAction::SetTrue) => words.push(flag),
            (Value::Bool(false), ArgAction::SetTrue) | (Value::Null, _) => {
                return Err(EngineError::Invalid(format!(
                    "{flag}: the command line cannot say {value} (its default is {})",
                    defaults.get(&name).unwrap_or(&Value::Null)
                )));
            }
            _ => {
                let w = word(value, arg.get_value_delimiter(), &name)?;
                // A value that starts with '-' would read as a flag.
                if w.starts_with('-') {
                    words.push(format!("{flag}={w}"));
                } else {
                    words.extend([flag, w]);
                }
            }
        }
    }
    words.extend(positionals);
    if P::SEEDED && seed != DEFAULT_SEED {
        words.extend(["--seed".to_owned(), seed.to_string()]);
    }
    if let Some(out) = output {
        words.extend(["-o".to_owned(), quoted(out)]);
    }
    Ok(words.join(" "))
}

fn as_object<P: serde::Serialize>(p: &P) -> Result<serde_json::Map<String, Value>> {
    match serde_json::to_value(p) {
        Ok(Value::Object(m)) => Ok(m),
        _ => Err(EngineError::Invalid(
            "parameters that are not an object".into(),
        )),
    }
}

/// One value as the CLI reads it: a list joined by the flag's delimiter (a
/// size's `x` where it has none), a choice or a number as JSON writes it.
fn word(value: &Value, delimiter: Option<char>, name: &str) -> Result<String> {
    Ok(match value {
        Value::String(s) => quoted(s),
        // A whole float as an integer (`6`, not JSON's `6.0`): clap reads either.
        Value::Number(n) => match n.as_f64() {
            Some(x) if n.is_f64() && x.fract() == 0.0 && x.abs() < 1e15 => format!("{x:.0}"),
            _ => n.to_string(),
        },
        Value::Bool(b) => b.to_string(),
        Value::Array(items) => {
            let items = items
                .iter()
                .map(|v| word(v, None, name))
                .collect::<Result<Vec<_>>>()?;
            items.join(&delimiter.map_or("x".to_owned(), String::from))
        }
        Value::Null | Value::Object(_) => {
            return Err(EngineError::Invalid(format!(
                "{name}: the command line cannot say {value}"
            )));
        }
    })
}

/// `s` as one shell word.
fn quoted(s: &str) -> String {
    let plain = !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_./:,=+@%".contains(c));
    if plain {
        s.to_owned()
    } else {
        format!("'{}'", s.replace('\'', r"'\''"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_are_quoted_only_when_a_shell_needs_it() {
        assert_eq!(quoted("out/h.npy"), "out/h.npy");
        assert_eq!(quoted("my file.ply"), "'my file.ply'");
        assert_eq!(quoted("it's"), r"'it'\''s'");
        assert_eq!(quoted(""), "''");
    }
}
