//! The example scenes of `crates/subdiv/scenes`, built into the library so
//! that every front end offers the same ones (issue #36): the CLI's
//! `asperity subdiv example:rock`, Python's `asperity.subdiv("example:rock")`,
//! the Blender add-on's kinds. One per procedure of velho-perlin §4.2 (Figs.
//! 3–5, 7, 9).
//!
//! [`Example::with`] gives a scene's text with its levels, seed, and the main
//! detail's size and spacing set — the knobs the add-on shows. The main detail
//! is the scene's last `[[detail]]`; its size is the field that scales the
//! procedure (see [`size_field`]).

use toml::{Table, Value};

/// A built-in example scene.
#[derive(Clone, Copy, Debug)]
pub struct Example {
    /// Its name (`example:NAME`).
    pub name: &'static str,
    /// The scene file's name in `crates/subdiv/scenes`.
    pub file: &'static str,
    /// The scene's TOML text.
    pub text: &'static str,
}

/// Every example, in the order the front ends list them.
pub const EXAMPLES: &[Example] = &[
    Example {
        name: "rock",
        file: "rock.toml",
        text: include_str!("../scenes/rock.toml"),
    },
    Example {
        name: "berry",
        file: "berry.toml",
        text: include_str!("../scenes/berry.toml"),
    },
    Example {
        name: "tentacle",
        file: "tentacle.toml",
        text: include_str!("../scenes/tentacle.toml"),
    },
    Example {
        name: "mushroom",
        file: "mushroom_planet.toml",
        text: include_str!("../scenes/mushroom_planet.toml"),
    },
    Example {
        name: "spur",
        file: "spurs.toml",
        text: include_str!("../scenes/spurs.toml"),
    },
];

/// The example called `name`.
pub fn example(name: &str) -> Option<&'static Example> {
    EXAMPLES.iter().find(|e| e.name == name)
}

/// The field that sets a procedure's size: rock and fbm `amplitude`, berry
/// `radius`, tentacle `length`, mushroom and spur `height`.
pub fn size_field(procedure: &str) -> Option<&'static str> {
    Some(match procedure {
        "rock" | "fbm" => "amplitude",
        "berry" => "radius",
        "tentacle" => "length",
        "mushroom" | "spur" | "mine" => "height",
        _ => return None,
    })
}

fn number(v: &Value) -> Option<f64> {
    v.as_float().or_else(|| v.as_integer().map(|i| i as f64))
}

impl Example {
    fn table(&self) -> Table {
        self.text.parse().expect("the built-in scenes parse")
    }

    /// The first paragraph of the scene file's leading comment.
    pub fn description(&self) -> String {
        self.text
            .lines()
            .map_while(|l| l.strip_prefix('#'))
            .map(str::trim)
            .collect::<Vec<_>>()
            .join(" ")
    }

    /// The scene's subdivision levels and seed (7 where it names none).
    pub fn levels_and_seed(&self) -> (usize, u64) {
        let t = self.table();
        let int = |k: &str, d: i64| t.get(k).and_then(Value::as_integer).unwrap_or(d);
        (int("levels", 0) as usize, int("seed", 7) as u64)
    }

    fn main_detail(t: &Table) -> Option<&Table> {
        t.get("detail")?.as_array()?.last()?.as_table()
    }

    /// The main detail's size field and value, where it has one (a number,
    /// not an animated pair).
    pub fn size(&self) -> Option<(&'static str, f64)> {
        let t = self.table();
        let d = Self::main_detail(&t)?;
        let field = size_field(d.get("type")?.as_str()?)?;
        Some((field, number(d.get(field)?)?))
    }

    /// The main detail's seed spacing, where it places seeds by spacing.
    pub fn spacing(&self) -> Option<f64> {
        let t = self.table();
        number(Self::main_detail(&t)?.get("spacing")?)
    }

    /// The scene's text with `levels` (details placed at levels the surface
    /// lacks keep those it has, or level 1), `seed`, and the main detail's
    /// `size` and `spacing`, each where given.
    ///
    /// # Errors
    /// A size or spacing for a scene whose main detail has none, or one that is
    /// not a positive finite number.
    pub fn with(
        &self,
        levels: Option<usize>,
        seed: Option<u64>,
        size: Option<f64>,
        spacing: Option<f64>,
    ) -> Result<String, String> {
        let mut t = self.table();
        if let Some(l) = levels {
            t.insert("levels".into(), Value::Integer(l as i64));
        }
        if let Some(s) = seed {
            t.insert("seed".into(), Value::Integer(s as i64));
        }
        let details = t.get_mut("detail").and_then(Value::as_array_mut);
        for d in details
            .into_iter()
            .flatten()
            .filter_map(Value::as_table_mut)
        {
            if let (Some(l), Some(Value::Array(at))) = (levels, d.get("levels")) {
                let kept: Vec<Value> = at
                    .iter()
                    .filter(|x| x.as_integer().is_some_and(|x| x as usize <= l))
                    .cloned()
                    .collect();
                let kept = if kept.is_empty() {
                    vec![Value::Integer(1)]
                } else {
                    kept
                };
                d.insert("levels".into(), Value::Array(kept));
            }
        }
        let positive = |what: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(Value::Float(v))
            } else {
                Err(format!("{what} must be a positive number, got {v}"))
            }
        };
        let mut main = t
            .get_mut("detail")
            .and_then(Value::as_array_mut)
            .and_then(|a| a.last_mut())
            .and_then(Value::as_table_mut);
        if let Some(v) = size {
            let field = main
                .as_deref()
                .and_then(|d| size_field(d.get("type")?.as_str()?));
            match (main.as_deref_mut(), field) {
                (Some(d), Some(field)) => d.insert(field.into(), positive("size", v)?),
                _ => return Err(format!("example {} has no detail size", self.name)),
            };
        }
        if let Some(v) = spacing {
            match main.filter(|d| d.contains_key("spacing")) {
                Some(d) => d.insert("spacing".into(), positive("spacing", v)?),
                None => return Err(format!("example {} places no detail by spacing", self.name)),
            };
        }
        Ok(toml::to_string(&t).expect("a TOML table serialises"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_example_parses_and_has_a_description_and_a_size() {
        for e in EXAMPLES {
            crate::scene::parse(e.text, 0.0).unwrap_or_else(|err| panic!("{}: {err}", e.name));
            assert!(e.description().len() > 20, "{}", e.name);
            assert!(e.size().is_some(), "{}", e.name);
            let (levels, _) = e.levels_and_seed();
            assert!(levels >= 4, "{}", e.name);
        }
    }

    #[test]
    fn with_sets_the_knobs_and_keeps_the_rest() {
        let berry = example("berry").unwrap();
        let text = berry.with(Some(2), Some(11), Some(0.2), Some(0.9)).unwrap();
        let scene = crate::scene::parse(&text, 0.0).unwrap();
        assert_eq!((scene.levels, scene.seed), (2, 11));
        let t: Table = text.parse().unwrap();
        let d = t["detail"]
            .as_array()
            .unwrap()
            .last()
            .unwrap()
            .as_table()
            .unwrap();
        assert_eq!(d["radius"].as_float(), Some(0.2));
        assert_eq!(d["spacing"].as_float(), Some(0.9));
        // placed at the levels the surface has
        assert!(
            d["levels"]
                .as_array()
                .unwrap()
                .iter()
                .all(|l| l.as_integer().unwrap() <= 2)
        );
        // unchanged without knobs (but for comments and layout)
        let same: Table = berry.with(None, None, None, None).unwrap().parse().unwrap();
        assert_eq!(same, berry.table());
        assert!(
            example("rock")
                .unwrap()
                .with(None, None, None, Some(1.0))
                .is_err()
        );
        assert!(berry.with(None, None, Some(-1.0), None).is_err());
    }
}
