//! The job parameters' contract (issue #36), checked on a real job (DLA):
//! records run the same job again, missing fields take the defaults and
//! unknown ones are refused, ranges come from the schema the front ends show,
//! one lattice rule serves every front end, choices parse and print their names.

use asperity_engine::growth::dla::{DlaParams, SeedShape, Sides};
use asperity_engine::params::*;
use serde_json::json;

#[test]
fn a_record_runs_the_same_job_again() {
    let p = DlaParams {
        seed_shape: SeedShape::Plane,
        size: Some(LatticeSize::new(&[64, 32, 48]).unwrap()),
        sides: Sides::Walls,
        ..DlaParams::DEFAULT
    };
    let r = record(&p, 11);
    assert_eq!(r["job"], "growth dla");
    assert_eq!(r["schema_version"], SCHEMA_VERSION);
    assert_eq!(r["seed"], 11);
    assert_eq!(r["size"], json!([64, 32, 48]));
    assert_eq!(r["sides"], "walls");
    let back = parse::<DlaParams>(&r).unwrap();
    assert_eq!(back.params, p);
    assert_eq!(back.seed, Some(11));
    // the record lists the fields in the struct's order
    let keys: Vec<&String> = r.as_object().unwrap().keys().collect();
    assert_eq!(keys.len(), 3 + field_names::<DlaParams>().len());
    assert_eq!(
        field_names::<DlaParams>()[..3],
        ["seed_shape", "size", "dim"]
    );
}

#[test]
fn missing_fields_take_the_defaults_and_unknown_ones_are_refused() {
    let p = parse::<DlaParams>(&json!({"particles": 500}))
        .unwrap()
        .params;
    assert_eq!(
        p,
        DlaParams {
            particles: 500,
            ..DlaParams::DEFAULT
        }
    );
    let e = parse::<DlaParams>(&json!({"particle": 500})).unwrap_err();
    assert_eq!(e.kind(), asperity_engine::ErrorKind::Type);
    assert!(e.to_string().contains("no parameter \"particle\""), "{e}");
    let e = parse::<DlaParams>(&json!({"job": "growth rd"})).unwrap_err();
    assert!(
        e.to_string().contains("for \"growth rd\", not growth dla"),
        "{e}"
    );
    let e = parse::<DlaParams>(&json!({"schema_version": 99})).unwrap_err();
    assert!(e.to_string().contains("schema version 99"), "{e}");
    let e = parse::<DlaParams>(&json!({"particles": "many"})).unwrap_err();
    assert_eq!(e.kind(), asperity_engine::ErrorKind::Type, "{e}");
    let e = parse::<DlaParams>(&json!({"seed_shape": "blob"})).unwrap_err();
    assert_eq!(e.kind(), asperity_engine::ErrorKind::Invalid, "{e}");
    assert!(
        e.to_string().starts_with("⟨seed_shape⟩: unknown variant"),
        "{e}"
    );
}

#[test]
fn ranges_come_from_the_schema() {
    let cases = [
        (json!({"stick": 0.0}), "⟨stick⟩ must be in (0, 1], got 0"),
        (json!({"stick": 1.5}), "⟨stick⟩ must be in (0, 1], got 1.5"),
        (json!({"dim": 4}), "⟨dim⟩ must be in [2, 3], got 4"),
        (
            json!({"launch_gap": 0.5}),
            "⟨launch_gap⟩ must be in [1, 10000], got 0.5",
        ),
        (
            json!({"launch_gap": 1e18}),
            "⟨launch_gap⟩ must be in [1, 10000], got 1000000000000000000",
        ),
        (
            json!({"particles": 0}),
            "⟨particles⟩ must be in [1, 10000000000], got 0",
        ),
    ];
    for (v, want) in cases {
        let e = parse::<DlaParams>(&v).unwrap_err();
        assert_eq!(e.to_string(), want);
    }
    // NaN and infinities (null once serialised) are refused by name
    let nan = DlaParams {
        stick: f64::NAN,
        ..DlaParams::DEFAULT
    };
    assert_eq!(
        validate(&nan).unwrap_err().to_string(),
        "⟨stick⟩ must be a finite number"
    );
    // the bounds a front end shows are those the check uses
    let d = describe::<DlaParams>();
    let stick = d["fields"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["name"] == "stick")
        .unwrap();
    assert_eq!(stick["exclusiveMinimum"], 0.0);
    assert_eq!(stick["maximum"], 1.0);
    assert_eq!(stick["default"], 1.0);
    let shape = &d["fields"][0];
    assert_eq!(shape["name"], "seed_shape");
    assert_eq!(
        shape["choices"].as_array().unwrap().len(),
        SeedShape::ALL.len()
    );
    assert_eq!(shape["choices"][1]["value"], "plane");
}

#[test]
fn one_lattice_rule_for_every_front_end() {
    let n = LatticeSize::new(&[64]).unwrap();
    assert_eq!(n.resolve(3).unwrap(), [64, 64, 64]);
    assert_eq!(n.resolve(2).unwrap(), [64, 1, 64]);
    let xz: LatticeSize = "64x32".parse().unwrap();
    assert_eq!(xz.resolve(2).unwrap(), [64, 1, 32]);
    assert!(xz.resolve(3).is_err());
    let xyz: LatticeSize = serde_json::from_value(json!([8, 1, 16])).unwrap();
    assert_eq!(xyz.resolve(2).unwrap(), [8, 1, 16]);
    assert_eq!(xyz.resolve(3).unwrap(), [8, 1, 16]);
    let one: LatticeSize = serde_json::from_value(json!(5)).unwrap();
    assert_eq!(one, n_of(5));
    assert!("0x4x4".parse::<LatticeSize>().is_err());
    assert!(serde_json::from_value::<LatticeSize>(json!([1, 2, 3, 4])).is_err());
    assert_eq!(xyz.to_string(), "8x1x16");
}

fn n_of(n: usize) -> LatticeSize {
    LatticeSize::new(&[n]).unwrap()
}

#[test]
fn choices_parse_and_print_their_names() {
    assert_eq!("Walls".parse::<Sides>().unwrap(), Sides::Walls);
    assert_eq!(Sides::Periodic.to_string(), "periodic");
    assert!(
        "wall"
            .parse::<Sides>()
            .unwrap_err()
            .contains("periodic, walls")
    );
    assert_eq!(serde_json::to_value(SeedShape::Image).unwrap(), "image");
}

/// A parameters file is read up to its limit, whatever its size on disk
/// says: a special file that never ends (`/dev/zero` reports no size) is
/// refused after 16 MiB, a real file over the limit too, both naming it.
#[test]
fn a_parameters_file_is_read_no_further_than_its_limit() {
    let message = |p: &std::path::Path| read_file(p).unwrap_err().to_string();
    let zero = std::path::Path::new("/dev/zero");
    if zero.exists() {
        let m = message(zero);
        assert!(
            m.contains("/dev/zero holds more than 16777216 bytes"),
            "{m}"
        );
    }
    let dir = tempfile::tempdir().unwrap();
    let big = dir.path().join("big.json");
    std::fs::write(&big, vec![b' '; (16 << 20) + 1]).unwrap();
    assert!(message(&big).contains("big.json holds more than"));
    let ok = dir.path().join("ok.json");
    std::fs::write(&ok, br#"{"particles": 5}"#).unwrap();
    assert_eq!(read_file(&ok).unwrap()["particles"], 5);
}

/// Every numeric parameter of every job has both bounds in the schema that
/// the CLI, Python and Blender show and `validate` enforces (#54): a value
/// past them is refused before any work, naming the parameter and the bound.
/// A new parameter without a bound fails here, naming it; list items (sizes,
/// windows, weights) and the forms of a parameter (a number or a text) too.
#[test]
fn every_numeric_parameter_has_both_bounds() {
    fn resolve<'a>(
        root: &'a serde_json::Value,
        node: &'a serde_json::Value,
    ) -> &'a serde_json::Value {
        match node.get("$ref").and_then(|r| r.as_str()) {
            Some(r) => r
                .strip_prefix("#/")
                .map(|p| p.split('/').fold(root, |n, k| &n[k]))
                .unwrap_or(node),
            None => node,
        }
    }
    fn numeric_leaves<'a>(
        root: &'a serde_json::Value,
        node: &'a serde_json::Value,
        out: &mut Vec<&'a serde_json::Value>,
    ) {
        let node = resolve(root, node);
        for key in ["anyOf", "oneOf", "allOf"] {
            for b in node
                .get(key)
                .and_then(|b| b.as_array())
                .into_iter()
                .flatten()
            {
                numeric_leaves(root, b, out);
            }
        }
        if let Some(items) = node.get("items") {
            numeric_leaves(root, items, out);
        }
        for b in node
            .get("prefixItems")
            .and_then(|b| b.as_array())
            .into_iter()
            .flatten()
        {
            numeric_leaves(root, b, out);
        }
        let ty = node.get("type");
        let numeric = |t: &serde_json::Value| t == "number" || t == "integer";
        let is_numeric = match ty {
            Some(serde_json::Value::Array(ts)) => ts.iter().any(numeric),
            Some(t) => numeric(t),
            None => false,
        };
        if is_numeric {
            out.push(node);
        }
    }
    let mut missing = Vec::new();
    let mut count = 0;
    for job in asperity_engine::jobs::jobs() {
        let schema = (job.schema)();
        let props = schema["properties"]
            .as_object()
            .cloned()
            .unwrap_or_default();
        for (name, field) in &props {
            let mut leaves = Vec::new();
            numeric_leaves(&schema, field, &mut leaves);
            for leaf in leaves {
                count += 1;
                let low = leaf.get("minimum").or(leaf.get("exclusiveMinimum"));
                let high = leaf.get("maximum").or(leaf.get("exclusiveMaximum"));
                if low.is_none() || high.is_none() {
                    missing.push(format!(
                        "{} {name}: {}{}",
                        job.name,
                        if low.is_none() { "no minimum " } else { "" },
                        if high.is_none() { "no maximum" } else { "" }
                    ));
                }
            }
        }
    }
    assert!(count >= 180, "{count} numeric parameters");
    assert!(
        missing.is_empty(),
        "{} of {count} without both bounds:\n{}",
        missing.len(),
        missing.join("\n")
    );
}

/// The command line of a job's parameters, parsed by the CLI's own argument
/// definitions, gives the parameters back: for the defaults and for each
/// field set in turn to every choice, `true`, or a bound or a value inside
/// its range (as the schema describes them), where the job accepts it.
fn command_lines_round_trip<P>() -> usize
where
    P: asperity_engine::params::JobParams + clap::Args + clap::FromArgMatches + PartialEq,
{
    command_lines_round_trip_from::<P>(json!({}))
}

/// As [`command_lines_round_trip`], with `required` (the fields a job has no
/// default for) set in every variant.
fn command_lines_round_trip_from<P>(required: serde_json::Value) -> usize
where
    P: asperity_engine::params::JobParams + clap::Args + clap::FromArgMatches + PartialEq,
{
    use asperity_engine::params::{command_line, describe, parse};
    let described = describe::<P>();
    let mut defaults = serde_json::to_value(P::default()).unwrap();
    for (k, v) in required.as_object().unwrap() {
        defaults[k] = v.clone();
    }
    let mut variants = vec![defaults.clone()];
    for field in described["fields"].as_array().unwrap() {
        let name = field["name"].as_str().unwrap();
        let mut values: Vec<serde_json::Value> = Vec::new();
        if let Some(choices) = field["choices"].as_array() {
            values.extend(choices.iter().map(|c| c["name"].clone()));
        }
        if field["type"] == "boolean" {
            values.push(json!(true));
        }
        if field["type"] == "integer" || field["type"] == "number" {
            for bound in ["minimum", "maximum"] {
                if let Some(b) = field[bound].as_f64().filter(|b| b.abs() <= 1e6) {
                    values.push(if field["type"] == "integer" {
                        json!(b as i64)
                    } else {
                        json!(b)
                    });
                }
            }
            values.push(if field["type"] == "integer" {
                json!(3)
            } else {
                json!(0.375)
            });
        }
        for v in values {
            let mut variant = defaults.clone();
            variant[name] = v;
            variants.push(variant);
        }
    }
    let mut checked = 0;
    for variant in variants {
        let Ok(parsed) = parse::<P>(&variant) else {
            continue;
        };
        let p = parsed.params;
        let Ok(line) = command_line(&p, 11, Some("out.ply")) else {
            continue;
        };
        let words: Vec<&str> = line.split(' ').collect();
        assert_eq!(
            words[..2].join(" "),
            format!("asperity {}", P::JOB.split(' ').next().unwrap())
        );
        // The job's words, then its arguments; -o and --seed are the CLI's own.
        let job_words = P::JOB.split(' ').count();
        let args: Vec<&str> = words[1 + job_words..]
            .iter()
            .copied()
            .take_while(|w| *w != "--seed" && *w != "-o")
            .collect();
        let mut cmd = P::augment_args(clap::Command::new("job").no_binary_name(true));
        // Arguments of the CLI's own that a job's flags name (subdiv's
        // scene file and frames conflict with some).
        for id in ["scene", "frames"] {
            if cmd.get_arguments().all(|a| a.get_id() != id) {
                cmd = cmd.arg(clap::Arg::new(id).long(id));
            }
        }
        let matches = cmd
            .try_get_matches_from(args.iter().map(|w| w.trim_matches('\'')))
            .unwrap_or_else(|e| panic!("{line}: {e}"));
        let back = P::from_arg_matches(&matches).unwrap_or_else(|e| panic!("{line}: {e}"));
        assert!(back == p, "{line} gives other parameters");
        assert!(line.contains("--seed 11") == P::SEEDED, "{line}");
        assert!(line.ends_with("-o out.ply"), "{line}");
        checked += 1;
    }
    checked
}

#[test]
fn every_job_s_command_line_gives_its_parameters_back() {
    use asperity_engine::{
        analyze, ca, files, growth, ifs, reconstruct, render, subdiv, surfca, synthesis,
    };
    let counts = [
        command_lines_round_trip::<growth::RdParams>(),
        command_lines_round_trip::<growth::RdsrParams>(),
        command_lines_round_trip::<growth::BdParams>(),
        command_lines_round_trip::<growth::dla::DlaParams>(),
        command_lines_round_trip::<reconstruct::LevelSetParams>(),
        command_lines_round_trip::<reconstruct::DlaTerrainParams>(),
        command_lines_round_trip::<reconstruct::RdsrSphereParams>(),
        command_lines_round_trip_from::<ca::CaRunParams>(json!({"rule": 450})),
        command_lines_round_trip_from::<ca::CaRuleParams>(json!({"rule": 450})),
        command_lines_round_trip::<ca::CaGalleryParams>(),
        command_lines_round_trip::<ca::FacetParams>(),
        command_lines_round_trip::<ca::InterpolateParams>(),
        command_lines_round_trip::<surfca::SurfaceCaParams>(),
        command_lines_round_trip::<subdiv::SubdivParams>(),
        command_lines_round_trip::<ifs::IfsPresetParams>(),
        command_lines_round_trip::<ifs::IfsCurveParams>(),
        command_lines_round_trip::<ifs::IfsSurfaceParams>(),
        command_lines_round_trip::<ifs::IfsDcfParams>(),
        command_lines_round_trip::<ifs::IfsSdcfParams>(),
        command_lines_round_trip::<ifs::IfsCurvatureParams>(),
        command_lines_round_trip::<analyze::AnalyzeParams>(),
        command_lines_round_trip_from::<analyze::FilterParams>(json!({"lambda_c": 8.0})),
        command_lines_round_trip::<synthesis::FbmParams>(),
        command_lines_round_trip::<render::RenderParams>(),
        command_lines_round_trip::<files::ConvertParams>(),
        command_lines_round_trip::<files::InfoParams>(),
    ];
    assert_eq!(
        counts.len(),
        asperity_engine::jobs::jobs().len(),
        "a job is missing here"
    );
    let total: usize = counts.iter().sum();
    println!("{total} command lines parsed back ({counts:?})");
    assert!(counts.iter().all(|&n| n >= 1), "{counts:?}");
    assert!(total >= 300, "{total}");
}
