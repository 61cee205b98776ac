//! `foldsim overlaps` and `foldsim::verify::overlap`: the overlap of two bodies measured from
//! a run's poses alone, against depths known by construction, and read from a written CSV as
//! from the run in memory.

mod common;

use foldsim::output::table::{Poses, Table, poses_from_table};
use foldsim::verify::overlap::{Solids, deepest_overlaps};

/// `examples/contact-panel-hub.toml`'s two bodies (a 1 × 1 × 0.3 m box hub centred on its
/// body origin, a 1.0 × 0.6 m panel 2 cm thick) placed by hand, one CSV row each: the panel
/// lying on the hub's top face (z = 0.15 m) sunk 3 mm into it; standing on its long edge
/// (turned 90° about x), the edge 2 mm into the face; 1 cm above it.
const PLACED: &str = "t,hub_R_x,hub_R_y,hub_R_z,hub_q_w,hub_q_x,hub_q_y,hub_q_z,panel_R_x,panel_R_y,panel_R_z,panel_q_w,panel_q_x,panel_q_y,panel_q_z
0,0,0,0,1,0,0,0,0,0,0.157,1,0,0,0
1,0,0,0,1,0,0,0,0,0,0.448,0.7071067811865476,0.7071067811865476,0,0
2,0,0,0,1,0,0,0,0,0,0.17,1,0,0,0
";

/// The known depths come back: 3 mm through the faces and 2 mm for the edge, the same with
/// the rim rounded as the samples describe it (its outermost point, on the mid-plane, is the
/// sharp outline's) as with sharp prisms; the separated row adds nothing. GJK/EPA on these
/// polytopes finds the separating face exactly; the rounded rim is built 1e-9 m short of the
/// outline (a sliver that makes parry's hull a solid), so the bound is 2e-9 m.
#[test]
fn placed_bodies_overlap_by_their_known_depths() {
    let s = common::scenario("examples/contact-panel-hub.toml");
    let dir = common::tmp("overlaps", "placed");
    let csv = dir.join("placed.csv");
    std::fs::write(&csv, PLACED).unwrap();
    let (poses, warnings) = poses_from_table(&s.model, &Table::read(&csv).unwrap()).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let row = |k: usize| Poses {
        times: vec![poses.times[k]],
        r_in_n: vec![poses.r_in_n[k].clone()],
        quat: vec![poses.quat[k].clone()],
    };
    for kind in [Solids::Sampled, Solids::Sharp] {
        for (k, depth) in [(0, 0.003), (1, 0.002)] {
            let found = deepest_overlaps(&s.model, &row(k), kind, None).unwrap();
            assert_eq!(found.len(), 1, "{kind:?} row {k}: {found:?}");
            let o = found[0];
            println!("{kind:?} row {k}: {:.12e} m", o.depth);
            assert!((o.depth - depth).abs() < 2e-9, "{kind:?} row {k}: {} m against {depth} m", o.depth);
            assert!((o.of_thickness - depth / 0.02).abs() < 1e-7 && o.bodies == (0, 1));
        }
        assert!(deepest_overlaps(&s.model, &row(2), kind, None).unwrap().is_empty(), "{kind:?}: apart");
        // Over the three rows: the deepest, at its row's time.
        let all = deepest_overlaps(&s.model, &poses, kind, None).unwrap();
        assert!(all.len() == 1 && (all[0].depth - 0.003).abs() < 2e-9 && all[0].t == 0.0, "{all:?}");
    }
}

/// The command prints the pairs and fails above `--fail-above`, naming the pair: 3 mm is 15 %
/// of the panel's 2 cm.
#[test]
fn the_command_reports_and_fails_above_its_bound() {
    let dir = common::tmp("overlaps", "command");
    let csv = dir.join("placed.csv");
    std::fs::write(&csv, PLACED).unwrap();
    let run = |extra: &[&str]| {
        let out = common::foldsim()
            .arg("overlaps")
            .arg(common::repo("examples/contact-panel-hub.toml"))
            .arg("--csv")
            .arg(&csv)
            .args(extra)
            .output()
            .unwrap();
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stdout).to_string(),
            String::from_utf8_lossy(&out.stderr).to_string(),
        )
    };
    let (code, out, err) = run(&["--fail-above", "0.2"]);
    assert_eq!(code, Some(0), "{out}{err}");
    assert!(out.contains("hub / panel: 3.000e-3 m (15.00 % of the thinner's thickness) at t = 0 s"), "{out}");
    let (code, _, err) = run(&["--fail-above", "0.1", "--sharp"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("hub and panel overlap by 3.000e-3 m") && err.contains("--fail-above 0.1"), "{err}");
    let (code, _, err) = run(&["--fail-above=-1"]);
    assert!(code == Some(1) && err.contains("--fail-above -1: give a fraction"), "{err}");
}

/// A run's CSV as written gives the same overlaps as the run's rows in memory (the CSV keeps
/// every digit: the same to 1e-12 m), here the panel-hub example's swing back, its sharp
/// corner 0.44 mm into the hub (docs/contact.md §4; the rounded rim stays out of it).
#[test]
fn a_written_run_measures_as_the_run_in_memory() {
    let s = common::scenario("examples/contact-panel-hub.toml");
    let dir = common::tmp("overlaps", "written");
    let csv = dir.join("run.csv");
    let mut rows = Vec::new();
    let mut sink = foldsim::output::CsvSink::create(&csv, &s.columns).unwrap();
    let mut both = |o: &foldsim::observe::Observation| -> Result<(), String> {
        rows.push(o.clone());
        foldsim::simulate::Sink::record(&mut sink, o)
    };
    foldsim::simulate::simulate(&s.model, &s.initial, &s.settings, &mut both, None).unwrap();
    sink.finish().unwrap();
    let (written, _) = poses_from_table(&s.model, &Table::read(&csv).unwrap()).unwrap();
    let from_csv = deepest_overlaps(&s.model, &written, Solids::Sharp, None).unwrap();
    let in_memory = deepest_overlaps(&s.model, &Poses::from_observations(&rows), Solids::Sharp, None).unwrap();
    println!("panel-hub: {:?} from the CSV, {:?} in memory", from_csv.first(), in_memory.first());
    assert_eq!(from_csv.len(), in_memory.len());
    for (a, b) in from_csv.iter().zip(&in_memory) {
        assert!((a.depth - b.depth).abs() < 1e-12 && a.t == b.t && a.bodies == b.bodies, "{a:?} {b:?}");
    }
    assert!(from_csv[0].depth > 1e-4 && from_csv[0].of_thickness < 0.1, "{:?}", from_csv[0]);
}

/// Two hinged plates meet along their crease, and the check leaves a strip of one thickness
/// along it out of each; a plate narrower than that beside its crease (here the z-fold
/// example's second panel cut to 15 mm across, its 2-cm thickness) leaves nothing to measure:
/// the check says so, naming the pair, rather than measuring the crease as an overlap.
#[test]
fn a_plate_within_one_thickness_of_its_crease_is_named() {
    let text = std::fs::read_to_string(common::repo("examples/contact-zfold.toml")).unwrap();
    let narrow = text
        .replacen(
            "name = \"p1\"\nshape = { polygon = [[-0.5, -0.4, 0.0], [0.5, -0.4, 0.0], [0.5, 0.4, 0.0], [-0.5, 0.4, 0.0]]",
            "name = \"p1\"\nshape = { polygon = [[-0.0075, -0.4, 0.0], [0.0075, -0.4, 0.0], [0.0075, 0.4, 0.0], [-0.0075, 0.4, 0.0]]",
            1,
        )
        .replacen("a = { child_com = [0.5, -0.01, 0.0], roll_deg = -90.0 }", "a = { child_com = [0.0075, -0.01, 0.0], roll_deg = -90.0 }", 1)
        .replacen("a0 = { position = [0.5, 0.0, -0.01], roll_deg = 90.0 }", "a0 = { position = [0.0075, 0.0, -0.01], roll_deg = 90.0 }", 1);
    assert!(narrow.contains("[-0.0075, -0.4, 0.0]") && narrow.contains("child_com = [0.0075"), "the edits apply");
    let s = foldsim::scenario::Scenario::from_toml(&narrow, "narrow.toml").unwrap_or_else(|e| panic!("{e}"));
    let (y, _) = foldsim::kinematics::initial_state(&s.model, &s.initial);
    let n = s.model.bodies.len();
    let motions: Vec<_> = (0..n).map(|i| foldsim::state::BodyMotion::from_state(&y, i)).collect();
    let poses = Poses {
        times: vec![0.0],
        r_in_n: vec![motions.iter().map(|m| m.r_in_n).collect()],
        quat: vec![motions.iter().map(|m| foldsim::math::quat_from_dcm(&m.dcm_n_b)).collect()],
    };
    let err = deepest_overlaps(&s.model, &poses, Solids::Sharp, None).unwrap_err();
    assert!(err.contains("p0 and p1") && err.contains("within one thickness (0.02 m)"), "{err}");
}
