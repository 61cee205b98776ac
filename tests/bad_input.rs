//! Bad scenario input: every case must give an error naming the file, the line (where the
//! input has one) and the key or name, and saying what would be valid; never a panic.

use foldsim::scenario::Scenario;
use foldsim::simulate::Integrator;

const GOOD: &str = r#"
[run]
duration = 1.0
output_step = 0.1
integrator = "dop853"
rtol = 1e-9
atol = 1e-9

[[body]]
name = "hub"
mass = 100.0
inertia = [100.0, 100.0, 100.0]

[[body]]
name = "p1"
mass = 10.0
inertia = [1.0, 1.0, 1.0]

[[body]]
name = "p2"
mass = 10.0
inertia = [1.0, 1.0, 1.0]

[[hinge]]
name = "h1"
parent = "hub"
child = "p1"
a0 = { position = [0.75, 0.0, 0.0] }
a = { child_com = [1.0, 0.0, 0.0] }
law = { type = "paper-linear", k_f = 100.0, k_theta = 10.0 }

[[hinge]]
name = "h2"
parent = "p1"
child = "p2"
a0 = { position = [1.0, 0.0, 0.0] }
a = { child_com = [1.0, 0.0, 0.0] }
law = { type = "euler-potential", k_f = 100.0, k_theta = 10.0 }

[initial.hinge.h1]
delta = [0.01, 0.0, 0.0]
"#;

/// Line (1-based) of the last line of the text containing `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    let lines: Vec<&str> = text.lines().collect();
    lines.iter().rposition(|l| l.contains(needle)).unwrap_or_else(|| panic!("no line with {needle}")) + 1
}

/// Applies `edit` to GOOD, expects an error at the line containing `at` (if given) whose
/// message contains every word of `words`.
fn expect_error(edit: impl Fn(&str) -> String, at: Option<&str>, words: &[&str]) {
    let text = edit(GOOD);
    let err = match Scenario::from_toml(&text, "bad.toml") {
        Ok(_) => panic!("accepted bad input:\n{text}"),
        Err(e) => e,
    };
    let msg = err.to_string();
    assert!(msg.starts_with("bad.toml"), "error must name the file: {msg}");
    if let Some(at) = at {
        let line = line_of(&text, at);
        assert_eq!(err.location.map(|l| l.0), Some(line), "error must point at line {line} ({at}): {msg}");
    }
    for w in words {
        assert!(msg.contains(w), "error should mention '{w}': {msg}");
    }
}

#[test]
fn good_input_is_accepted() {
    Scenario::from_toml(GOOD, "good.toml").unwrap();
}

#[test]
fn malformed_toml() {
    expect_error(|t| t.replace("mass = 100.0", "mass = = 100.0"), Some("mass = = 100.0"), &["bad.toml"]);
    expect_error(|t| t.replace("[run]", "[run"), Some("[run"), &[]);
}

#[test]
fn unknown_keys() {
    expect_error(|t| t.replace("mass = 100.0", "mass = 100.0\ncolour = \"red\""), Some("colour"), &["colour"]);
    expect_error(|t| t.replace("duration = 1.0", "duration = 1.0\nrtoll = 1e-9"), Some("rtoll"), &["rtoll"]);
    expect_error(
        |t| {
            t.replace("a0 = { position = [0.75, 0.0, 0.0] }", "a0 = { position = [0.75, 0.0, 0.0], yaw_degrees = 3.0 }")
        },
        Some("yaw_degrees"),
        &["yaw_degrees", "h1"],
    );
    expect_error(
        |t| t.replace("delta = [0.01, 0.0, 0.0]", "delta = [0.01, 0.0, 0.0]\nspin = 1.0"),
        Some("spin = 1.0"),
        &["spin"],
    );
    expect_error(|t| t.replace("type = \"paper-linear\"", "type = \"paper-linear\", k_x = 1.0"), Some("k_x"), &["k_x"]);
}

#[test]
fn unknown_names() {
    expect_error(|t| t.replace("child = \"p1\"", "child = \"p9\""), Some("child = \"p9\""), &["p9", "hub, p1, p2"]);
    expect_error(
        |t| t.replace("[initial.hinge.h1]", "[initial.hinge.h7]"),
        Some("[initial.hinge.h7]"),
        &["h7", "h1, h2"],
    );
    expect_error(
        |t| t.replace("integrator = \"dop853\"", "integrator = \"euler\""),
        Some("integrator"),
        &["euler", "dop853"],
    );
    expect_error(
        |t| t.replace("type = \"paper-linear\"", "type = \"linear\""),
        Some("type = \"linear\""),
        &["linear", "paper-linear", "euler-potential"],
    );
}

#[test]
fn duplicate_names() {
    expect_error(|t| t.replacen("name = \"p2\"", "name = \"p1\"", 1), Some("name = \"p1\""), &["duplicate body", "p1"]);
    expect_error(|t| t.replace("name = \"h2\"", "name = \"h1\""), None, &["duplicate hinge", "h1"]);
}

#[test]
fn hinge_to_itself() {
    expect_error(|t| t.replace("parent = \"p1\"", "parent = \"p2\""), Some("name = \"h2\""), &["h2", "itself"]);
}

#[test]
fn disconnected_graph() {
    // p2 hangs from nothing: remove hinge h2 entirely.
    let cut = |t: &str| {
        let start = t.find("[[hinge]]\nname = \"h2\"").unwrap();
        let end = t.find("[initial.hinge.h1]").unwrap();
        format!("{}{}", &t[..start], &t[end..])
    };
    expect_error(cut, Some("name = \"p2\""), &["p2", "not connected"]);
}

#[test]
fn hub_as_child() {
    expect_error(
        |t| t.replace("parent = \"hub\"\nchild = \"p1\"", "parent = \"p1\"\nchild = \"hub\""),
        Some("name = \"h1\""),
        &["h1", "hub", "child"],
    );
}

#[test]
fn bad_mass() {
    expect_error(|t| t.replacen("mass = 10.0", "mass = 0.0", 1), Some("mass = 0.0"), &["mass", "> 0"]);
    expect_error(|t| t.replacen("mass = 10.0", "mass = -3.0", 1), Some("mass = -3.0"), &["mass", "p1"]);
}

#[test]
fn bad_inertia() {
    let line = "inertia = [1.0, 1.0, 1.0]";
    expect_error(
        |t| t.replacen(line, "inertia = [[1.0, 0.2, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]", 1),
        Some("0.2"),
        &["symmetric", "p1"],
    );
    expect_error(|t| t.replacen(line, "inertia = [1.0, -1.0, 1.0]", 1), Some("-1.0"), &["positive definite"]);
    expect_error(|t| t.replacen(line, "inertia = [1.0, 1.0, 3.0]", 1), Some("3.0]"), &["triangle inequality"]);
    expect_error(|t| t.replacen(line, "inertia = [1.0, 1.0]", 1), Some("[1.0, 1.0]"), &["inertia", "principal"]);
}

#[test]
fn non_finite_numbers() {
    expect_error(|t| t.replacen("mass = 10.0", "mass = nan", 1), Some("mass = nan"), &["body[1].mass", "finite"]);
    expect_error(
        |t| t.replace("delta = [0.01, 0.0, 0.0]", "delta = [0.01, inf, 0.0]"),
        Some("inf"),
        &["initial.hinge.h1.delta[1]", "finite"],
    );
    expect_error(|t| t.replacen("k_theta = 10.0 }", "k_theta = -inf }", 1), Some("-inf"), &["k_theta", "finite"]);
}

#[test]
fn bad_times() {
    expect_error(|t| t.replace("duration = 1.0", "duration = -1.0"), Some("duration"), &["run.duration", "> 0"]);
    expect_error(
        |t| t.replace("output_step = 0.1", "output_step = 0.0"),
        Some("output_step"),
        &["run.output_step", "> 0"],
    );
    expect_error(
        |t| t.replace("integrator = \"dop853\"\nrtol = 1e-9\natol = 1e-9", "integrator = \"rk4\"\nstep = -0.01"),
        Some("step = -0.01"),
        &["run.step", "> 0"],
    );
    expect_error(|t| t.replace("rtol = 1e-9", "rtol = -1e-9"), Some("rtol"), &["run.rtol"]);
    expect_error(|t| t.replace("rtol = 1e-9\n", ""), Some("[run]"), &["run.rtol"]);
    // Generalized-α: without a step it is adaptive and needs its tolerances; ρ∞ is a
    // spectral radius, and only it takes one.
    let ga = |extra: &'static str| {
        move |t: &str| t.replace("integrator = \"dop853\"", &format!("integrator = \"generalized-alpha\"\n{extra}"))
    };
    let adaptive = Scenario::from_toml(&ga("")(GOOD), "good.toml").unwrap();
    assert!(matches!(adaptive.settings.integrator, Integrator::GeneralizedAlpha { step: None, .. }));
    expect_error(
        |t| ga("")(t).replace("rtol = 1e-9\n", ""),
        Some("[run]"),
        &["run.rtol", "generalized-alpha", "error"],
    );
    expect_error(ga("step = 0.01\nrho_inf = 1.5"), Some("rho_inf = 1.5"), &["run.rho_inf", "0", "1"]);
    expect_error(
        |t| t.replace("integrator = \"dop853\"", "integrator = \"dop853\"\nrho_inf = 0.9"),
        Some("rho_inf = 0.9"),
        &["run.rho_inf", "dop853"],
    );
    expect_error(
        |t| {
            t.replace(
                "integrator = \"dop853\"\nrtol = 1e-9\natol = 1e-9",
                "integrator = \"rk4\"\nstep = 0.01\nrho_inf = 0.9",
            )
        },
        Some("rho_inf = 0.9"),
        &["run.rho_inf", "rk4"],
    );
    expect_error(
        ga("step = 0.01\nerror_norm = \"state\""),
        Some("error_norm"),
        &["run.error_norm", "generalized-alpha"],
    );
}

#[test]
fn conflicting_or_misplaced_values() {
    expect_error(
        |t| {
            t.replace(
                "a0 = { position = [0.75, 0.0, 0.0] }",
                "a0 = { position = [0.75, 0.0, 0.0], yaw = 0.1, yaw_deg = 5.0 }",
            )
        },
        Some("yaw_deg = 5.0"),
        &["yaw", "yaw_deg"],
    );
    expect_error(
        |t| t.replace("a0 = { position = [0.75, 0.0, 0.0] }", "a0 = \"assembly\""),
        Some("assembly"),
        &["assembled"],
    );
    expect_error(
        |t| {
            t.replace(
                "type = \"euler-potential\", k_f = 100.0",
                "type = \"euler-potential\", k_f = [[1.0, 2.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]",
            )
        },
        Some("2.0, 0.0"),
        &["symmetric"],
    );
    expect_error(
        |t| t.to_string() + "\n[initial.body.hub]\nyaw_deg = 3.0\n",
        Some("[initial.body.hub]"),
        &["hub", "initial.hub"],
    );
    expect_error(
        |t| {
            t.replace("delta = [0.01, 0.0, 0.0]", "delta = [0.01, 0.0, 0.0]\nyaw_deg = 2.0")
                + "\n[initial.body.p1]\nyaw_deg = 3.0\n"
        },
        Some("[initial.body.p1]"),
        &["p1", "h1", "one or the other"],
    );
}

#[test]
fn loop_hinge_cannot_take_initial_values() {
    let looped = GOOD.to_string()
        + r#"
[[hinge]]
name = "h3"
parent = "hub"
child = "p2"
a0 = "assembled"
a = { child_com = [1.0, 0.0, 0.0] }
law = { type = "paper-linear", k_f = 100.0, k_theta = 10.0 }
"#;
    Scenario::from_toml(&looped, "loop.toml").expect("an assembled loop hinge is valid");
    let with_initial = looped.clone() + "\n[initial.hinge.h3]\nyaw_deg = 1.0\n";
    let e = Scenario::from_toml(&with_initial, "loop.toml").unwrap_err().to_string();
    assert!(e.contains("h3") && e.contains("assembled"), "{e}");
}

/// Bad directional laws and tables: located errors naming the hinge and direction.
#[test]
fn bad_directional_laws() {
    let law = "law = { type = \"paper-linear\", k_f = 100.0, k_theta = 10.0 }";
    let directional = |dirs: &str| format!("law = {{ type = \"directional\", angles = \"euler\", {dirs} }}");
    let six = "x = { k = 1.0 }, y = { k = 1.0 }, z = { k = 1.0 }, rx = { k = 1.0 }, ry = { k = 1.0 }, rz = { k = 1.0 }";
    let with = |d: String| move |t: &str| t.replacen(law, &d, 1);
    expect_error(
        with(directional(&six.replace(", rz = { k = 1.0 }", ""))),
        Some("directional"),
        &["h1", "rz", "missing"],
    );
    expect_error(
        with(directional(&six.replace("rz = { k = 1.0 }", "rz = { k = 1.0, free = true }"))),
        Some("directional"),
        &["rz", "exactly one"],
    );
    // The shorthand words are "free" and "locked"; anything else names what is valid.
    expect_error(
        with(directional(&six.replace("ry = { k = 1.0 }", "ry = \"lockd\""))),
        Some("directional"),
        &["lockd", "\"free\"", "\"locked\"", "k = "],
    );
    // A key the parser does not know: the hinge is named, not only the line.
    expect_error(
        with(directional(&six.replace("rz = { k = 1.0 }", "rz = { k = 1.0, lock = true }"))),
        Some("directional"),
        &["hinge 'h1'", "lock", "locked"],
    );
    let shorthand = GOOD.replacen(law, &directional(&six.replace("ry = { k = 1.0 }", "ry = \"free\"")), 1);
    assert!(Scenario::from_toml(&shorthand, "ok.toml").is_ok(), "ry = \"free\" is valid");
    expect_error(
        with(directional(&six.replace("rz = { k = 1.0 }", "rz = { k = 1.0, rest_degrees = 3.0 }"))),
        Some("directional"),
        &["rest_degrees"],
    );
    expect_error(
        with(directional(&six.replace("x = { k = 1.0 }", "x = { k = 1.0, rest_deg = 3.0 }"))),
        Some("directional"),
        &["x", "rest_deg", "rotational"],
    );
    expect_error(
        with(directional(&six.replace(
            "rz = { k = 1.0 }",
            "rz = { table = { file = \"no-such.csv\", interpolation = \"linear\", outside = \"clamp\" } }",
        ))),
        Some("directional"),
        &["rz", "no-such.csv"],
    );
    expect_error(
        with(directional(&six.replace(
            "rz = { k = 1.0 }",
            "rz = { table = { points = [[0.0, 1.0], [0.0, 2.0]], interpolation = \"linear\", outside = \"clamp\" } }",
        ))),
        Some("directional"),
        &["rz", "increase strictly"],
    );
    expect_error(
        with(directional(&six.replace(
            "rz = { k = 1.0 }",
            "rz = { table = { points = [[0.0, 1.0], [1.0, 2.0]], interpolation = \"cubic\", outside = \"clamp\" } }",
        ))),
        Some("cubic"),
        &["cubic", "pchip"],
    );
    expect_error(
        with(directional(&six.replace("rz = { k = 1.0 }", "rz = { tape_spring = { increasing = { points = [[-1.0, -1.0], [1.0, 1.0]], interpolation = \"linear\", outside = \"extend\" }, decreasing = { points = [[-1.0, -2.0], [1.0, 2.0]], interpolation = \"linear\", outside = \"extend\" }, transition_stiffness = 10.0 } }"))),
        Some("directional"),
        &["rz", "below the decreasing"],
    );
    expect_error(
        with(directional(&six.replace(
            "rz = { k = 1.0 }",
            "rz = { k = 1.0, stop = { at_deg = 0.0, free = \"up\", stiffness = 1.0, damping = 0.0 } }",
        ))),
        Some("free = \"up\""),
        &["above", "below"],
    );
    expect_error(
        with(format!(
            "law = {{ type = \"directional\", angles = \"rotation-vector\", {} }}",
            six.replace("rx = { k = 1.0 }", "rx = { locked = true }")
        )),
        Some("directional"),
        &["rx", "euler"],
    );
    expect_error(with(directional(six).replace("angles = \"euler\", ", "")), Some("directional"), &["angles"]);
    expect_error(
        with("law = { type = \"paper-linear\", k_f = 1.0, k_theta = 1.0, rz = { k = 1.0 } }".to_string()),
        Some("rz = {"),
        &["rz", "directional"],
    );
}

/// The reader's messages in the scenario's words: the key of a duplicate; "a number", "a
/// list of 3 numbers", "a table like { child_com = … }", "key" rather than Rust types and
/// serde's "field".
#[test]
fn reader_messages_speak_the_files_language() {
    // Inside a [[body]] the reader locates the body (its header), which the message names.
    expect_error(
        |g| g.replacen("mass = 10.0\n", "mass = 10.0\nmass = 11.0\n", 1),
        None,
        &["p1", "duplicate key 'mass'"],
    );
    expect_error(
        |g| g.replace("duration = 1.0", "duration = 1.0\nduration = 2.0"),
        Some("duration = 2.0"),
        &["duplicate key 'duration'"],
    );
    expect_error(
        |g| g.replacen("mass = 10.0", "mass = \"ten\"", 1),
        Some("\"ten\""),
        &["got the text \"ten\"", "expected a number"],
    );
    expect_error(
        |g| g.replacen("a = { child_com = [1.0, 0.0, 0.0] }", "a = 5", 1),
        Some("a = 5"),
        &["got the whole number", "child_com = [x, y, z]"],
    );
    expect_error(
        |g| g.replacen("child_com = [1.0, 0.0, 0.0]", "child_com = [1.0, 0.0]", 1),
        Some("child_com = [1.0, 0.0]"),
        &["list of length 2", "list of 3 numbers"],
    );
    expect_error(
        |g| g.replacen("mass = 10.0", "masss = 10.0", 1),
        Some("masss"),
        &["unknown key 'masss'", "valid keys"],
    );
    expect_error(
        |g| g.replace("atol = 1e-9", "atol = 1e-9\nmax_steps = 99999999999999999999"),
        Some("max_steps"),
        &["too large"],
    );
    for edit in [
        |g: &str| g.replacen("mass = 10.0", "mass = \"ten\"", 1),
        |g: &str| g.replacen("a = { child_com = [1.0, 0.0, 0.0] }", "a = 5", 1),
        |g: &str| g.replace("atol = 1e-9", "atol = 1e-9\nmax_steps = 99999999999999999999"),
        |g: &str| g.replacen("mass = 10.0", "masss = 10.0", 1),
    ] {
        let e = Scenario::from_toml(&edit(GOOD), "bad.toml").unwrap_err();
        for jargon in ["f64", "i64", "i128", "struct", "Raw", "field", "`"] {
            assert!(!e.message.contains(jargon), "'{jargon}' in: {e}");
        }
    }
}

/// One policy for every law: stiffness and damping that would create energy are refused
/// (paper-linear accepted a negative k_f and c_theta, and ran until its steps collapsed).
#[test]
fn negative_springs_and_dampers_are_refused_by_every_law() {
    for law in ["paper-linear", "euler-potential", "rotation-vector"] {
        for (key, value) in [("k_f", "-100.0"), ("k_theta", "[10.0, -1.0, 10.0]"), ("c_f", "-1.0"), ("c_theta", "-0.5")]
        {
            let edit = |g: &str| {
                let line =
                    format!("law = {{ type = \"{law}\", k_f = 100.0, k_theta = 10.0, c_f = 1.0, c_theta = 1.0 }}");
                let line = line.replace(
                    &format!(
                        "{key} = {}",
                        if key.starts_with('k') { if key == "k_f" { "100.0" } else { "10.0" } } else { "1.0" }
                    ),
                    &format!("{key} = {value}"),
                );
                g.replacen("law = { type = \"paper-linear\", k_f = 100.0, k_theta = 10.0 }", &line, 1)
            };
            expect_error(edit, Some(&format!("{key} = {value}")), &["h1", key, "positive semidefinite"]);
        }
    }
    let directional = |k: &str, damping: &str| {
        format!(
            "law = {{ type = \"directional\", angles = \"euler\", x = {{ k = 100.0 }}, y = {{ k = 100.0 }}, z = {{ k = 100.0 }}, rx = {{ k = 10.0 }}, ry = {{ k = 10.0 }}, rz = {{ k = {k}, damping = {damping} }} }}"
        )
    };
    let base = "law = { type = \"paper-linear\", k_f = 100.0, k_theta = 10.0 }";
    expect_error(
        |g| g.replacen(base, &directional("-1.0", "0.0"), 1),
        Some("k = -1.0"),
        &["h1", "rz", "k must be ≥ 0"],
    );
    expect_error(
        |g| g.replacen(base, &directional("1.0", "-0.1"), 1),
        Some("damping = -0.1"),
        &["h1", "rz", "damping must be ≥ 0"],
    );
    // A table may fall (snap-through is physical).
    let falling = "law = { type = \"directional\", angles = \"euler\", x = { k = 100.0 }, y = { k = 100.0 }, z = { k = 100.0 }, rx = { k = 10.0 }, ry = { k = 10.0 }, rz = { table = { points = [[-1.0, 1.0], [0.0, 0.0], [1.0, -1.0], [2.0, 3.0]], interpolation = \"linear\", outside = \"extend\" } } }";
    Scenario::from_toml(&GOOD.replacen(base, falling, 1), "ok.toml").unwrap_or_else(|e| panic!("{e}"));
}

/// Locks that repeat each other are refused when the scenario loads, naming the hinge that
/// closes the loop, its line, and the locked hinges it shares bodies with (it named none, and
/// only when the run started).
#[test]
fn redundant_locks_name_the_hinge_that_closes_the_loop() {
    let all = "law = { type = \"directional\", angles = \"euler\", x = \"locked\", y = \"locked\", z = \"locked\", rx = \"locked\", ry = \"locked\", rz = { k = 10.0 } }";
    let text = GOOD
        .replace("law = { type = \"paper-linear\", k_f = 100.0, k_theta = 10.0 }", all)
        .replace("law = { type = \"euler-potential\", k_f = 100.0, k_theta = 10.0 }", all)
        .replace("[initial.hinge.h1]\ndelta = [0.01, 0.0, 0.0]\n", "")
        + "\n[[hinge]]\nname = \"h3\"\nparent = \"hub\"\nchild = \"p2\"\na0 = \"assembled\"\na = { child_com = [1.0, 0.0, 0.0] }\n"
        + &format!("{all}\n");
    let e = Scenario::from_toml(&text, "loop.toml").unwrap_err();
    assert!(e.message.contains("hinge 'h3'") && e.message.contains("repeat") && e.message.contains("h1"), "{e}");
    assert_eq!(e.location.map(|l| l.0), Some(line_of(&text, "name = \"h3\"")), "{e}");
}

/// An angle in radians above a turn is accepted with a located warning (degrees meant?).
#[test]
fn radians_above_a_turn_are_warned_of() {
    let text = GOOD.replace("[initial.hinge.h1]\n", "[initial.hinge.h1]\nyaw = 30.0\n");
    let s = Scenario::from_toml(&text, "warn.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.warnings.len(), 1, "{:?}", s.warnings);
    let w = &s.warnings[0];
    assert!(w.starts_with(&format!("warn.toml:{}:", line_of(&text, "yaw = 30.0"))) && w.contains("yaw_deg"), "{w}");
    let fine = GOOD.replace("[initial.hinge.h1]\n", "[initial.hinge.h1]\nyaw = 3.0\nyaw_deg_unused = 0\n");
    assert!(Scenario::from_toml(&fine.replace("yaw_deg_unused = 0\n", ""), "ok.toml").unwrap().warnings.is_empty());
}

/// A body's shape: mass and inertia follow from a plate or a box and a density exactly; given
/// values that disagree, a shape off the centre of mass, a density without a shape and a bad
/// polygon are refused at their keys.
#[test]
fn shapes_give_mass_properties_or_located_errors() {
    let p1 = "name = \"p1\"\nmass = 10.0\ninertia = [1.0, 1.0, 1.0]";
    assert!(GOOD.contains(p1));
    // A 2 m × 1 m plate (centred), 5 kg/m², 0.1 m thick: 10 kg; I = m/12 (1 + 0.01, 4 + 0.01, 4 + 1).
    let plate = "name = \"p1\"\nshape = { polygon = [[-1.0, -0.5, 0.0], [1.0, -0.5, 0.0], [1.0, 0.5, 0.0], [-1.0, 0.5, 0.0]], thickness = 0.1 }\ndensity = 5.0";
    let s = Scenario::from_toml(&GOOD.replacen(p1, plate, 1), "plate.toml").unwrap_or_else(|e| panic!("{e}"));
    let b = &s.model.bodies[1];
    let m = 10.0;
    let expected = [m / 12.0 * 1.01, m / 12.0 * 4.01, m / 12.0 * 5.0];
    assert!((b.mass - m).abs() < 1e-12 && b.shape.is_some());
    for (k, e) in expected.iter().enumerate() {
        assert!((b.inertia_in_body[(k, k)] - e).abs() < 1e-12, "I{k}{k} = {} vs {e}", b.inertia_in_body[(k, k)]);
    }
    // Given mass and inertia that agree are accepted; disagreeing ones refused at the key.
    let agree = format!("{plate}\nmass = 10.0\ninertia = [{:?}, {:?}, {:?}]", expected[0], expected[1], expected[2]);
    Scenario::from_toml(&GOOD.replacen(p1, &agree, 1), "agree.toml").unwrap_or_else(|e| panic!("{e}"));
    expect_error(
        |g| g.replacen(p1, &format!("{plate}\nmass = 11.0"), 1),
        Some("mass = 11.0"),
        &["p1", "disagrees", "density"],
    );
    expect_error(
        |g| g.replacen(p1, &format!("{plate}\ninertia = [1.0, 2.0, 2.5]"), 1),
        Some("inertia = [1.0, 2.0, 2.5]"),
        &["p1", "'inertia' disagrees"],
    );
    // A box from its mass alone.
    let boxed = "name = \"p1\"\nshape = { box = [1.0, 2.0, 3.0] }\nmass = 12.0";
    let s = Scenario::from_toml(&GOOD.replacen(p1, boxed, 1), "box.toml").unwrap_or_else(|e| panic!("{e}"));
    assert!((s.model.bodies[1].inertia_in_body[(0, 0)] - 13.0).abs() < 1e-12, "m/12 (b² + c²) = 13");
    // A cylinder about z from its mass: I_z = m r²/2 = 6, I_x = m (3r² + h²)/12 = 3.36.
    let cylinder = "name = \"p1\"\nshape = { cylinder = { radius = 1.0, height = 0.6 } }\nmass = 12.0";
    let s = Scenario::from_toml(&GOOD.replacen(p1, cylinder, 1), "cyl.toml").unwrap_or_else(|e| panic!("{e}"));
    let i = s.model.bodies[1].inertia_in_body;
    assert!((i[(2, 2)] - 6.0).abs() < 1e-12 && (i[(0, 0)] - 3.36).abs() < 1e-12 && (i[(1, 1)] - 3.36).abs() < 1e-12);
    expect_error(
        |g| g.replacen(p1, "name = \"p1\"\nshape = { cylinder = { radius = 0.0, height = 0.6 } }\nmass = 12.0", 1),
        Some("shape ="),
        &["p1", "cylinder's radius and height must be finite and > 0 m"],
    );
    expect_error(
        |g| {
            g.replacen(p1, "name = \"p1\"\nshape = { cylinder = { radius = 1.0, height = 0.6 }, box = [1.0, 1.0, 1.0] }\nmass = 12.0", 1)
        },
        Some("shape ="),
        &["p1", "a shape is one of", "cylinder = { radius = r, height = h }"],
    );
    // Off the centre of mass, a density without a shape, neither mass nor density, a crossed polygon.
    let off = "name = \"p1\"\nshape = { polygon = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0], [0.0, 1.0, 0.0]] }\ndensity = 5.0";
    expect_error(|g| g.replacen(p1, off, 1), Some("shape ="), &["p1", "centroid", "move the shape by [-1e0, -5e-1"]);
    expect_error(
        |g| g.replacen(p1, &format!("{p1}\ndensity = 3.0"), 1),
        Some("density = 3.0"),
        &["p1", "needs a 'shape'"],
    );
    expect_error(
        |g| g.replacen(p1, "name = \"p1\"\nshape = { box = [1.0, 1.0, 1.0] }", 1),
        Some("shape ="),
        &["p1", "'density'", "'mass'"],
    );
    let crossed = "name = \"p1\"\nshape = { polygon = [[-2.0, -1.0, 0.0], [2.0, -1.0, 0.0], [2.0, 1.0, 0.0], [-1.0, -2.0, 0.0], [-2.0, 1.0, 0.0]] }\ndensity = 1.0";
    expect_error(|g| g.replacen(p1, crossed, 1), Some("shape ="), &["p1", "cross"]);
    expect_error(|g| g.replacen(p1, "name = \"p1\"", 1), None, &["p1", "needs 'mass'"]);
}

/// `[initial.loop.NAME]` picks a loop hinge's branch (±180°, whole turns); the angles must
/// agree with the bodies' poses, name a loop hinge, and not repeat `[initial.hinge]`.
#[test]
fn loop_hinge_branches() {
    let with_loop = |extra: &str| {
        let t = GOOD.replace(
            "[initial.hinge.h1]",
            "[[hinge]]\nname = \"h3\"\nparent = \"hub\"\nchild = \"p2\"\na0 = \"assembled\"\na = { child_com = [1.0, 0.0, 0.0] }\nlaw = { type = \"euler-potential\", k_f = 100.0, k_theta = 10.0 }\n\n[initial.hinge.h1]",
        );
        format!("{t}\n{extra}")
    };
    // A whole turn of yaw is a branch, accepted and kept as the hinge's starting angle.
    let s = Scenario::from_toml(&with_loop("[initial.loop.h3]\nyaw = 6.283185307179586\n"), "good.toml").unwrap();
    let (_, refs) = foldsim::kinematics::initial_state(&s.model, &s.initial);
    assert!((refs[2].yaw - 2.0 * std::f64::consts::PI).abs() < 1e-12, "{:?}", refs[2]);
    expect_error(|_| with_loop("[initial.loop.h3]\nyaw = 1.0\n"), Some("[initial.loop.h3]"), &["h3", "must agree"]);
    expect_error(|_| with_loop("[initial.loop.h2]\nyaw = 0.0\n"), Some("[initial.loop.h2]"), &["h2", "tree hinge"]);
    expect_error(|_| with_loop("[initial.loop.h9]\nyaw = 0.0\n"), Some("[initial.loop.h9]"), &["h9", "h1, h2, h3"]);
    expect_error(
        |_| with_loop("[initial.loop.h1]\nyaw = 0.0\n"),
        Some("[initial.loop.h1]"),
        &["h1", "[initial.hinge.h1]"],
    );
}

/// Motors and the hub's control: every bad value named with its line and what is valid.
#[test]
fn bad_motors_and_control() {
    let add = |extra: &'static str| move |g: &str| format!("{g}\n{extra}");
    let motor = "[[motor]]\nname = \"m\"\nhinge = \"h1\"\n";
    for (extra, at, words) in [
        (format!("{motor}direction = \"rz\"\neffort = 1.0\n[[motor]]\nname = \"m\"\nhinge = \"h2\"\ndirection = \"rz\"\neffort = 1.0\n"), "name = \"m\"", vec!["second motor", "'m'"]),
        (format!("{motor}direction = \"yaw\"\neffort = 1.0\n"), "direction = \"yaw\"", vec!["motor 'm'", "\"rx\"", "yaw"]),
        ("[[motor]]\nname = \"m\"\nhinge = \"h9\"\ndirection = \"rz\"\neffort = 1.0\n".to_string(), "hinge = \"h9\"", vec!["no hinge 'h9'", "'h1'"]),
        (format!("{motor}direction = \"rz\"\n"), "name = \"m\"", vec!["either 'effort'", "'target'"]),
        (format!("{motor}direction = \"rz\"\ntarget = 1.0\nkp = 2.0\n"), "name = \"m\"", vec!["servo needs 'kd'"]),
        (format!("{motor}direction = \"rz\"\neffort = 1.0\nkp = 2.0\n"), "kp = 2.0", vec!["'kp' belongs to a servo"]),
        (format!("{motor}direction = \"x\"\ntarget_deg = 3.0\nkp = 1.0\nkd = 1.0\n"), "target_deg", vec!["'target_deg' is for angles"]),
        (format!("{motor}direction = \"rz\"\ntimes = [0.0, 1.0]\neffort = [1.0]\n"), "effort = [1.0]", vec!["one number per time"]),
        (format!("{motor}direction = \"rz\"\ntarget = 1.0\nkp = 1.0\nkd = 1.0\nlimit = -1.0\n"), "limit = -1.0", vec!["'limit' must be a finite number > 0"]),
        ("[control]\nlaw = \"pid\"\np = 1.0\n".to_string(), "law = \"pid\"", vec!["\"mrp_pd\"", "\"spin_hold\"", "pid"]),
        ("[control]\nlaw = \"mrp_pd\"\np = 1.0\ntarget = [1.0, 0.0, 0.0, 0.0]\n".to_string(), "law = \"mrp_pd\"", vec!["needs 'k'"]),
        ("[control]\nlaw = \"mrp_pd\"\nk = 1.0\np = 1.0\n".to_string(), "law = \"mrp_pd\"", vec!["needs 'target'"]),
        ("[control]\nlaw = \"mrp_pd\"\nk = 1.0\np = 1.0\ntarget = [1.0, 0.5, 0.0, 0.0]\n".to_string(), "target =", vec!["unit quaternion"]),
        ("[control]\nlaw = \"spin_hold\"\np = 1.0\nspin_axis = [0.0, 0.0, 1.0]\n".to_string(), "law = \"spin_hold\"", vec!["'spin_rate'"]),
        ("[control]\nlaw = \"spin_hold\"\nk = 1.0\np = 1.0\nspin_rate = 1.0\nspin_axis = [0.0, 0.0, 1.0]\n".to_string(), "k = 1.0", vec!["'k' is an attitude gain"]),
        ("[control]\nlaw = \"none\"\np = 1.0\n".to_string(), "p = 1.0", vec!["no gains"]),
        ("[control]\nlaw = \"rate_damping\"\np = 1.0\n[[control.wheel]]\nname = \"w\"\naxis = [0.0, 0.0, 0.0]\ninertia = 0.1\n".to_string(), "axis = [0.0, 0.0, 0.0]", vec!["wheel 'w'", "nonzero"]),
        ("[control]\nlaw = \"rate_damping\"\np = 1.0\n[[control.wheel]]\nname = \"w\"\naxis = [0.0, 0.0, 1.0]\ninertia = 200.0\n".to_string(), "[control]", vec!["body 'hub'", "not positive definite", "include its wheels"]),
        ("[control]\nlaw = \"rate_damping\"\np = 1.0\n[[control.wheel]]\nname = \"w\"\naxis = [0.0, 0.0, 1.0]\ninertia = 0.1\n[[control.thruster]]\nname = \"t\"\naxis = [1.0, 0.0, 0.0]\n".to_string(), "[control]", vec!["wheels or thrusters, not both"]),
        ("[control]\nlaw = \"rate_damping\"\np = 1.0\nmax_torque = 1.0\n[[control.wheel]]\nname = \"w\"\naxis = [0.0, 0.0, 1.0]\ninertia = 0.1\n".to_string(), "max_torque = 1.0", vec!["ideal torque's limit"]),
    ] {
        let extra: &'static str = Box::leak(extra.into_boxed_str());
        expect_error(add(extra), Some(at), &words);
    }
}
