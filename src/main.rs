//! `foldsim`: command-line front end of the foldsim library.

use clap::{Parser, Subcommand};
use foldsim::law::EventKind;
use foldsim::law::directional::DIRECTION_NAMES;
use foldsim::observe::Selection;
use foldsim::output::CsvSink;
#[cfg(feature = "animation")]
use foldsim::output::animation::Frames;
use foldsim::scenario::Scenario;
use foldsim::simulate::{RunReport, Sink, simulate};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

#[derive(Parser)]
#[command(
    name = "foldsim",
    version,
    about = "Deployment dynamics of folded spacecraft structures with flexible hinges"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scenario and write its outputs (docs/outputs.md) as CSV.
    Run {
        /// Scenario file (TOML; see docs/scenario.md).
        scenario: PathBuf,
        /// Output CSV. Default: `run.csv` from the scenario, else `<scenario name>.csv` in
        /// the current directory. It may not be one of the run's input files.
        #[arg(long)]
        csv: Option<PathBuf>,
        /// Columns to write, comma-separated names or patterns with * and ?, and the word
        /// `default` for the default set (overrides `run.columns`), e.g. `t,h*_yaw,hub_w_*`.
        #[arg(long, value_delimiter = ',')]
        columns: Option<Vec<String>>,
        /// Write the output even if it is estimated above 1 GiB.
        #[arg(long)]
        large_output: bool,
        /// Print nothing but errors.
        #[arg(long, short)]
        quiet: bool,
        /// Also write the run as an animated glTF binary (.glb; docs/outputs.md).
        #[cfg(feature = "animation")]
        #[arg(long)]
        animation: Option<PathBuf>,
        /// Frames per second of simulated time in the animation (default: one per output row).
        #[cfg(feature = "animation")]
        #[arg(long)]
        animation_fps: Option<f64>,
        /// Also write the viewer page of the run (as `foldsim view` does from the CSV).
        #[cfg(feature = "animation")]
        #[arg(long)]
        view: Option<PathBuf>,
    },
    /// Write an animated glTF binary (.glb) of a finished run from its CSV and its scenario.
    #[cfg(feature = "animation")]
    Animate {
        /// The run's scenario file.
        scenario: PathBuf,
        /// The run's CSV (it must hold every body's _R_x/y/z and yaw/pitch/roll columns).
        #[arg(long)]
        csv: PathBuf,
        /// The .glb file to write.
        #[arg(long, short)]
        output: PathBuf,
        /// Frames per second of simulated time (default: one per CSV row).
        #[arg(long)]
        fps: Option<f64>,
    },
    /// Write one self-contained HTML page that plays a finished run (works offline, from a
    /// file): the animation with play, pause, speed and a time slider, an orbiting camera,
    /// panels coloured by body or by fold angle, and a plot of output columns whose cursor
    /// follows the animation.
    #[cfg(feature = "animation")]
    View {
        /// The run's scenario file.
        scenario: PathBuf,
        /// The run's CSV (with every body's _R_x/y/z and yaw/pitch/roll columns).
        #[arg(long)]
        csv: PathBuf,
        /// The .html page to write.
        #[arg(long, short)]
        output: PathBuf,
        /// Columns to plot, comma-separated (default: the deployed fraction and spin rate of
        /// a large structure, else the first hinges' fold angles).
        #[arg(long, value_delimiter = ',')]
        columns: Vec<String>,
        /// Animation frames per second of simulated time (default: one per CSV row).
        #[arg(long)]
        fps: Option<f64>,
    },
    /// Run a sweep: many runs of a scenario with the values its [sweep] table draws
    /// (docs/sweep.md), in parallel, one summary row per run streamed to a CSV file.
    Sweep {
        /// Scenario file with a [sweep] table.
        scenario: PathBuf,
        /// Summary table to write (CSV). Default: `<scenario name>-sweep.csv` in the current
        /// directory. Written as `<file>.partial` until the last run is done.
        #[arg(long, short)]
        output: Option<PathBuf>,
        /// Worker threads (default: one per core).
        #[arg(long)]
        workers: Option<usize>,
        /// Number of runs (overrides sweep.runs).
        #[arg(long)]
        runs: Option<usize>,
        /// Seed of the draws (overrides sweep.seed).
        #[arg(long)]
        seed: Option<u64>,
        /// Print nothing but errors.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Write a generated structure as a scenario file.
    Generate {
        #[command(subcommand)]
        shape: Shape,
        /// Panel mass, kg (z-fold and grid; default 2).
        #[arg(long, global = true)]
        panel_mass: Option<f64>,
        /// Hinge translational stiffness, N/m.
        #[arg(long, default_value_t = 1e6, global = true)]
        k_translation: f64,
        /// Hinge stiffness of the two rotations off the fold axis, N·m/rad.
        #[arg(long, default_value_t = 1e3, global = true)]
        k_bending: f64,
        /// Hinge fold stiffness, N·m/rad.
        #[arg(long, default_value_t = 1.0, global = true)]
        k_fold: f64,
        /// Stowed fold angle (z-fold) or initial hub-hinge fold (grid), degrees (default 30).
        #[arg(long, global = true)]
        fold_deg: Option<f64>,
        /// Simulated time, s.
        #[arg(long, default_value_t = 10.0, global = true)]
        duration: f64,
        /// Integrator tolerance (rtol = atol).
        #[arg(long, default_value_t = 1e-8, global = true)]
        tolerance: f64,
        /// Scenario file to write.
        #[arg(long, short, global = true)]
        output: Option<PathBuf>,
    },
    /// Plot columns of an output CSV against time, as PNG.
    #[cfg(feature = "plot")]
    Plot {
        /// Output CSV of `foldsim run`.
        csv: PathBuf,
        /// Columns to plot, comma-separated (e.g. h1_yaw,h2_yaw).
        #[arg(long, value_delimiter = ',', required = true)]
        columns: Vec<String>,
        /// Show angle columns in degrees.
        #[arg(long)]
        degrees: bool,
        /// Title of the plot.
        #[arg(long, default_value = "")]
        title: String,
        /// PNG file to write.
        #[arg(long, short)]
        output: PathBuf,
    },
}

#[derive(Subcommand)]
enum Shape {
    /// A z-folded chain of panels off the hub.
    Zfold {
        /// Number of panels.
        #[arg(long)]
        panels: usize,
    },
    /// A grid of panels hinged to their neighbours (many loops).
    Grid {
        /// Rows of panels.
        #[arg(long)]
        rows: usize,
        /// Columns of panels.
        #[arg(long)]
        cols: usize,
    },
    /// A flasher: a flat disc of panels that wraps round a polygonal hub (docs/flasher.md),
    /// stowed at the start and stress-free deployed. Prints what it built (diameters, counts,
    /// loops, geometry checks, stowed folds and strain).
    #[command(allow_negative_numbers = true)]
    Flasher(Box<FlasherArgs>),
}

#[derive(clap::Args)]
struct FlasherArgs {
    /// Number of gores N (sides of the hub), ≥ 3.
    #[arg(long)]
    gores: usize,
    /// Rings of panels (nodes per major fold − 1), ≥ 1.
    #[arg(long)]
    rings: usize,
    /// Hub circumradius, m.
    #[arg(long, default_value_t = 1.0)]
    hub_radius: f64,
    /// Panel thickness, m (mass properties and shapes; the stowed wrap is the zero-thickness one).
    #[arg(long, default_value_t = 0.0)]
    thickness: f64,
    /// Mass per unit area of the panels, kg/m².
    #[arg(long, default_value_t = 1.0)]
    areal_density: f64,
    /// Hub mass, kg.
    #[arg(long, default_value_t = 100.0)]
    hub_mass: f64,
    /// Hub principal inertia about its centroid (x, y in its plane, z its axis), kg·m²,
    /// comma-separated. Default: a uniform disc of the hub's radius and mass.
    #[arg(long, value_delimiter = ',', num_args = 3)]
    hub_inertia: Option<Vec<f64>>,
    /// Panel model: quads (rigid, flat in both states), ring-quads (one ring each, strained
    /// when stowed) or triangles (a bending hinge on each quad's diagonal).
    #[arg(long, default_value = "triangles", value_parser = ["triangles", "quads", "ring-quads"])]
    panels: String,
    /// Fold damping of the creases, N·m·s/rad.
    #[arg(long, default_value_t = 0.0)]
    c_fold: f64,
    /// Bending stiffness of the diagonal hinges (triangle model), N·m/rad.
    #[arg(long, default_value_t = 1e3)]
    k_panel_bending: f64,
    /// Bending damping of the diagonal hinges (triangle model), N·m·s/rad.
    #[arg(long, default_value_t = 0.0)]
    c_panel_bending: f64,
    /// Translational damping of every hinge, N·s/m.
    #[arg(long, default_value_t = 0.0)]
    c_translation: f64,
    /// Damping of every hinge's two rotations off its fold axis, N·m·s/rad.
    #[arg(long, default_value_t = 0.0)]
    c_rotation: f64,
    /// Initial hub spin about its axis, rev/min.
    #[arg(long, default_value_t = 0.0)]
    spin_rpm: f64,
    /// Hold the stowed state until this time, s (run.release_at).
    #[arg(long)]
    release_at: Option<f64>,
    /// Output step, s (default: duration / 1000).
    #[arg(long)]
    output_step: Option<f64>,
    /// Integrator: dop853 or sdirk4 (stiff hinges on many panels).
    #[arg(long, default_value = "dop853", value_parser = ["dop853", "sdirk4"])]
    integrator: String,
    /// Print every hinge's stowed fold angle, not only the distinct ones.
    #[arg(long)]
    all_folds: bool,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        #[cfg(feature = "animation")]
        Command::Run { scenario, csv, columns, large_output, quiet, animation, animation_fps, view: page } => {
            let animation_target = animation.map(|path| (path, animation_fps));
            run(&scenario, csv, columns, large_output, quiet, animation_target).and_then(|csv| match page {
                Some(page) => view(&scenario, &csv, &page, animation_fps, &[]),
                None => Ok(()),
            })
        }
        #[cfg(not(feature = "animation"))]
        Command::Run { scenario, csv, columns, large_output, quiet } => {
            run(&scenario, csv, columns, large_output, quiet, None).map(|_| ())
        }
        #[cfg(feature = "animation")]
        Command::Animate { scenario, csv, output, fps } => animate(&scenario, &csv, &output, fps),
        #[cfg(feature = "animation")]
        Command::View { scenario, csv, output, columns, fps } => view(&scenario, &csv, &output, fps, &columns),
        Command::Sweep { scenario, output, workers, runs, seed, quiet } => {
            sweep(&scenario, output, workers, runs, seed, quiet)
        }
        Command::Generate {
            shape,
            panel_mass,
            k_translation,
            k_bending,
            k_fold,
            fold_deg,
            duration,
            tolerance,
            output,
        } => {
            if let Shape::Flasher(args) = shape {
                if panel_mass.is_some() || fold_deg.is_some() {
                    Err("--panel-mass and --fold-deg do not apply to a flasher: its panels' masses follow from --areal-density and their shapes, its folds from the geometry".to_string())
                } else {
                    let run = foldsim::generate::RunText { duration, tolerance, ..Default::default() };
                    generate_flasher(&args, k_translation, k_bending, k_fold, run, output)
                }
            } else {
                let p = foldsim::generate::Params {
                    panel_mass: panel_mass.unwrap_or(2.0),
                    k_translation,
                    k_bending,
                    k_fold,
                    fold_deg: fold_deg.unwrap_or(30.0),
                    duration,
                    tolerance,
                    ..Default::default()
                };
                generate(shape, &p, output)
            }
        }
        #[cfg(feature = "plot")]
        Command::Plot { csv, columns, degrees, title, output } => {
            foldsim::output::plot::plot_columns(&csv, &columns, degrees, &title, &output)
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

/// An option's key as the command line spells it: `k_fold` → `--k-fold`.
fn flag(key: &str) -> String {
    format!("--{}", key.replace('_', "-"))
}

fn generate(shape: Shape, p: &foldsim::generate::Params, output: Option<PathBuf>) -> Result<(), String> {
    use foldsim::generate::options::{grid_checked, zfold_checked};
    let text = match shape {
        Shape::Zfold { panels } => zfold_checked(panels, p, &flag)?,
        Shape::Grid { rows, cols } => grid_checked(rows, cols, p, &flag)?,
        Shape::Flasher(_) => unreachable!("flashers are written by generate_flasher"),
    };
    write_scenario(&text, output)
}

fn write_scenario(text: &str, output: Option<PathBuf>) -> Result<(), String> {
    match output {
        None => {
            print!("{text}");
            Ok(())
        }
        Some(output) => std::fs::write(&output, text).map_err(|e| format!("cannot write {}: {e}", output.display())),
    }
}

/// Writes a flasher's scenario (to `output`, or standard output) and prints its report (to
/// standard output, or standard error when the scenario goes there); the report also heads
/// the scenario as comments.
fn generate_flasher(
    a: &FlasherArgs,
    k_translation: f64,
    k_rotation: f64,
    k_fold: f64,
    run: foldsim::generate::RunText,
    output: Option<PathBuf>,
) -> Result<(), String> {
    use foldsim::generate::flasher::FlasherLaws;
    use foldsim::generate::options::{FlasherOptions, panel_model};
    let options = FlasherOptions {
        gores: a.gores,
        rings: a.rings,
        hub_radius: a.hub_radius,
        thickness: a.thickness,
        areal_density: a.areal_density,
        hub_mass: a.hub_mass,
        hub_inertia: a.hub_inertia.as_ref().map(|v| [v[0], v[1], v[2]]),
        panels: panel_model(&a.panels)?,
        laws: FlasherLaws {
            k_fold,
            c_fold: a.c_fold,
            k_bending: a.k_panel_bending,
            c_bending: a.c_panel_bending,
            k_translation,
            c_translation: a.c_translation,
            k_rotation,
            c_rotation: a.c_rotation,
        },
        spin_rpm: a.spin_rpm,
        duration: run.duration,
        output_step: a.output_step,
        tolerance: run.tolerance,
        integrator: a.integrator.clone(),
        release_at: a.release_at,
    };
    let (text, report) = options.scenario(&flag)?;
    let summary = report.text(a.all_folds);
    // The command that wrote it (without the output file), then the report, as comments.
    let mut command: Vec<String> = vec!["foldsim".into()];
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        if arg == "-o" || arg == "--output" {
            args.next();
        } else if !arg.starts_with("--output=") {
            command.push(arg);
        }
    }
    let commented: String = std::iter::once(format!("Written by: {}", command.join(" ")))
        .chain(report.text(false).lines().map(str::to_string))
        .map(|l| format!("# {l}\n"))
        .collect();
    let text = format!("{commented}{text}");
    if output.is_some() {
        print!("{summary}");
    } else {
        eprint!("{summary}");
    }
    write_scenario(&text, output)
}

/// Output estimated above this many bytes is refused unless `--large-output` is given.
const LARGE_OUTPUT: f64 = 1024.0 * 1024.0 * 1024.0;

/// Bytes a CSV field takes on average (shortest round-trip digits, sign, exponent, comma).
const BYTES_PER_FIELD: f64 = 22.0;

fn run(
    path: &Path,
    csv: Option<PathBuf>,
    columns: Option<Vec<String>>,
    large_output: bool,
    quiet: bool,
    animation: Option<(PathBuf, Option<f64>)>,
) -> Result<PathBuf, String> {
    let scenario = Scenario::from_file(path).map_err(|e| e.to_string())?;
    if let Some((glb, fps)) = &animation {
        check_animation_target(glb, *fps, &scenario.inputs)?;
    }
    for w in &scenario.warnings {
        eprintln!("warning: {w}");
    }
    let target = csv.or_else(|| scenario.csv.clone()).unwrap_or_else(|| {
        let stem = path.file_stem().map_or_else(|| "foldsim".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{stem}.csv"))
    });
    let columns = match columns {
        Some(patterns) => Selection::matching(&scenario.model, &patterns).map_err(|m| format!("--columns: {m}"))?,
        None => scenario.columns.clone(),
    };
    refuse_inputs(&target, &scenario.inputs)?;
    let settings = &scenario.settings;
    let rows = (settings.duration / settings.output_step).floor() + 2.0;
    let bytes = rows * columns.names.len() as f64 * BYTES_PER_FIELD;
    if bytes > LARGE_OUTPUT && !large_output {
        return Err(format!(
            "{}: this run would write about {:.1} GiB ({rows:.3e} rows of {} columns): raise run.output_step, choose fewer columns (run.columns or --columns), or pass --large-output to write it anyway",
            path.display(),
            bytes / LARGE_OUTPUT,
            columns.names.len()
        ));
    }
    let stale = target.is_file().then(|| target.clone());
    let mut sink = CsvSink::create(&target, &columns)?;
    let duration = settings.duration;

    // Ctrl-C stops the run at its next step, which then says where it stopped.
    let interrupted = Arc::new(AtomicBool::new(false));
    let flag = interrupted.clone();
    let _ = ctrlc::set_handler(move || flag.store(true, Ordering::SeqCst));

    let bar = (!quiet && std::io::stderr().is_terminal()).then(|| {
        let bar = ProgressBar::new(1000);
        bar.set_style(
            ProgressStyle::with_template("{spinner} t = {msg} [{bar:40}] {percent}% eta {eta}")
                .expect("static progress template")
                .progress_chars("=> "),
        );
        bar
    });
    let mut tick = |t: f64| {
        if let Some(b) = &bar {
            b.set_position((1000.0 * t / duration) as u64);
            b.set_message(format!("{t:.3} s"));
        }
        if interrupted.load(Ordering::SeqCst) { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
    };
    let mut frames = animation.as_ref().map(|(_, fps)| Frames::new(scenario.model.bodies.len(), *fps));
    let result = {
        let mut both = |o: &foldsim::observe::Observation| -> Result<(), String> {
            sink.record(o)?;
            if let Some(f) = frames.as_mut() {
                f.push(o);
            }
            Ok(())
        };
        simulate(&scenario.model, &scenario.initial, settings, &mut both, Some(&mut tick))
    };
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    match result {
        Ok(report) => {
            let written = sink.finish()?;
            if !quiet {
                print_report(&scenario, &report, &written);
            }
            if let (Some((glb, _)), Some(mut frames)) = (animation, frames) {
                frames.finish();
                write_animation(&scenario.model, &frames, &glb, quiet)?;
            }
            Ok(written)
        }
        Err(e) => {
            let partial = sink.partial_path().to_path_buf();
            drop(sink);
            let mut message =
                format!("{}: {e}\nthe rows written before it stopped are in {}", path.display(), partial.display());
            if let Some(old) = stale.filter(|old| *old != partial) {
                message.push_str(&format!("\n{} is an earlier run's complete output, left as it was", old.display()));
            }
            Err(message)
        }
    }
}

/// `foldsim sweep`: runs the sweep, streaming its rows to `<output>.partial`, renamed to
/// `output` once every run is done.
fn sweep(
    path: &Path,
    output: Option<PathBuf>,
    workers: Option<usize>,
    runs: Option<usize>,
    seed: Option<u64>,
    quiet: bool,
) -> Result<(), String> {
    let mut sweep = foldsim::sweep::Sweep::from_file(path).map_err(|e| e.to_string())?;
    if let Some(n) = runs {
        sweep.set_runs(n).map_err(|e| format!("--runs: {e}"))?;
    }
    if let Some(s) = seed {
        sweep.set_seed(s);
    }
    let workers = match workers {
        Some(0) => return Err("--workers must be at least 1".into()),
        Some(w) => w,
        None => std::thread::available_parallelism().map_or(1, |n| n.get()),
    };
    let target = output.unwrap_or_else(|| {
        let stem = path.file_stem().map_or_else(|| "foldsim".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{stem}-sweep.csv"))
    });
    if target.extension().is_some_and(|e| e.eq_ignore_ascii_case("parquet")) {
        return Err(format!(
            "{}: the command line writes the summary as CSV; for Parquet, run the sweep from Python (foldsim.sweep(...).to_parquet(...), docs/sweep.md)",
            target.display()
        ));
    }
    refuse_inputs(&target, &[path.to_path_buf()])?;
    let mut partial = target.clone().into_os_string();
    partial.push(".partial");
    let partial = PathBuf::from(partial);
    let file = std::fs::File::create(&partial).map_err(|e| format!("cannot write {}: {e}", partial.display()))?;
    let mut table = foldsim::sweep::CsvTable::new(std::io::BufWriter::new(file), sweep.header())?;

    let stop = Arc::new(AtomicBool::new(false));
    let flag = stop.clone();
    let _ = ctrlc::set_handler(move || flag.store(true, Ordering::SeqCst));
    let total = sweep.runs();
    let bar = (!quiet && std::io::stderr().is_terminal()).then(|| {
        let bar = ProgressBar::new(total as u64);
        bar.set_style(
            ProgressStyle::with_template("{spinner} run {pos}/{len} {msg} [{bar:40}] eta {eta}")
                .expect("static progress template")
                .progress_chars("=> "),
        );
        bar
    });
    let started = std::time::Instant::now();
    let mut failed = 0usize;
    let result = sweep.run(0..total, workers, &stop, &mut |row| {
        failed += usize::from(row.error.is_some());
        if let Some(b) = &bar {
            b.inc(1);
            b.set_message(format!("({failed} failed)"));
        }
        table.write(&row)
    });
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    table.finish()?;
    if let Err(e) = result {
        return Err(format!("{}: {e}\nthe rows of the runs done are in {}", path.display(), partial.display()));
    }
    std::fs::rename(&partial, &target)
        .map_err(|e| format!("cannot rename {} to {}: {e}", partial.display(), target.display()))?;
    if !quiet {
        println!(
            "foldsim sweep: {total} runs ({failed} failed) on {workers} workers in {:.2} s -> {}",
            started.elapsed().as_secs_f64(),
            target.display()
        );
    }
    Ok(())
}

#[cfg(not(feature = "animation"))]
struct Frames;

#[cfg(not(feature = "animation"))]
impl Frames {
    fn new(_: usize, _: Option<f64>) -> Self {
        Frames
    }
    fn push(&mut self, _: &foldsim::observe::Observation) {}
    fn finish(&mut self) {}
}

#[cfg(not(feature = "animation"))]
fn check_animation_target(_: &Path, _: Option<f64>, _: &[PathBuf]) -> Result<(), String> {
    Ok(())
}

#[cfg(not(feature = "animation"))]
fn write_animation(_: &foldsim::model::Model, _: &Frames, _: &Path, _: bool) -> Result<(), String> {
    Ok(())
}

/// Refuses an animation target that is an input, or a frame rate that is not positive.
#[cfg(feature = "animation")]
fn check_animation_target(glb: &Path, fps: Option<f64>, inputs: &[PathBuf]) -> Result<(), String> {
    if let Some(f) = fps
        && !(f.is_finite() && f > 0.0)
    {
        return Err(format!("the animation's frame rate must be a positive number of frames per second; got {f}"));
    }
    refuse_inputs(glb, inputs)
}

#[cfg(feature = "animation")]
fn write_animation(model: &foldsim::model::Model, frames: &Frames, glb: &Path, quiet: bool) -> Result<(), String> {
    let written = foldsim::output::animation::write_glb(model, frames, glb)?;
    if !quiet {
        println!(
            "  animation        {} frames, {:.1} MB -> {}",
            written.frames,
            written.bytes as f64 / 1e6,
            glb.display()
        );
    }
    Ok(())
}

/// A finished run read back for `animate` and `view`: its scenario, CSV, animation frames
/// and the rows they came from; `output` checked not to be one of its inputs.
#[cfg(feature = "animation")]
fn finished_run(
    scenario_path: &Path,
    csv: &Path,
    output: &Path,
    fps: Option<f64>,
) -> Result<(Scenario, foldsim::output::animation::Table, Frames, Vec<usize>), String> {
    use foldsim::output::animation::{Table, frames_from_table};
    let scenario = Scenario::from_file(scenario_path).map_err(|e| e.to_string())?;
    check_animation_target(output, fps, &scenario.inputs)?;
    let table = Table::read(csv)?;
    let (frames, kept) =
        frames_from_table(&scenario.model, &table, fps).map_err(|m| format!("{}: {m}", csv.display()))?;
    Ok((scenario, table, frames, kept))
}

/// `foldsim animate`: the animation of a finished run from its CSV's body columns.
#[cfg(feature = "animation")]
fn animate(scenario_path: &Path, csv: &Path, output: &Path, fps: Option<f64>) -> Result<(), String> {
    let (scenario, _, frames, _) = finished_run(scenario_path, csv, output, fps)?;
    write_animation(&scenario.model, &frames, output, false)
}

/// `foldsim view`: a self-contained page playing a finished run, beside a plot of `columns`.
#[cfg(feature = "animation")]
fn view(scenario_path: &Path, csv: &Path, output: &Path, fps: Option<f64>, columns: &[String]) -> Result<(), String> {
    let (scenario, table, frames, kept) = finished_run(scenario_path, csv, output, fps)?;
    let title = scenario.title.clone().unwrap_or_else(|| scenario_path.display().to_string());
    let html = foldsim::output::viewer::page(&title, &scenario.model, &table, &frames, &kept, columns)?;
    foldsim::output::animation::write_atomically(output, html.as_bytes())?;
    println!(
        "  viewer           {} frames, {:.1} MB -> {}",
        frames.times.len(),
        html.len() as f64 / 1e6,
        output.display()
    );
    Ok(())
}

/// Refuses an output path that is one of the run's inputs (the scenario or a table file):
/// writing there would destroy it.
fn refuse_inputs(target: &Path, inputs: &[PathBuf]) -> Result<(), String> {
    let same = |a: &Path, b: &Path| match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    };
    match inputs.iter().find(|input| same(target, input)) {
        Some(input) => Err(format!(
            "the output {} is an input of this run ({}): name another file with --csv",
            target.display(),
            input.display()
        )),
        None => Ok(()),
    }
}

fn print_report(scenario: &Scenario, r: &RunReport, csv: &Path) {
    let d = &r.drift;
    let rel = |x: f64, scale: f64| if scale > 0.0 { x / scale } else { x };
    println!("foldsim run: {}", scenario.title.as_deref().unwrap_or("(untitled)"));
    println!(
        "  bodies {}, hinges {} ({} loop), integrator {}",
        scenario.model.bodies.len(),
        scenario.model.hinges.len(),
        scenario.model.is_tree_hinge.iter().filter(|t| !**t).count(),
        scenario.settings.integrator.name()
    );
    println!("  simulated time   {:.6} s", r.simulated);
    println!("  wall time        {:.3} s", r.wall_seconds);
    println!("  steps            {} accepted, {} rejected", r.steps_accepted, r.steps_rejected);
    if r.drift.locks > 0 {
        println!("  rhs evaluations  {} ({} solving for engaged locks)", r.rhs_evaluations, r.constrained_evaluations);
    } else {
        println!("  rhs evaluations  {}", r.rhs_evaluations);
    }
    if r.jacobians > 0 {
        let how = if r.differenced_jacobians > 0 {
            "by finite differences: a hinge law without a dual form"
        } else {
            "exact, by dual numbers"
        };
        println!("  newton           {} iterations, {} Jacobians ({how})", r.newton_iterations, r.jacobians);
    }
    if let Some(t) = r.stiff_from {
        println!(
            "  note: from t = {t:.4} s the explicit steps were limited by stability, not accuracy: stiff hinges; integrator = \"sdirk4\" (implicit) suits this run better"
        );
    }
    println!("  output rows      {} -> {}", r.rows, csv.display());
    println!("  drift over the run (max |x(t) - x(0)|):");
    println!(
        "    linear momentum P   {:.3e} kg·m/s  ({:.3e} of Σ m|v|)",
        d.momentum,
        rel(d.momentum, d.momentum_scale)
    );
    println!(
        "    angular momentum H  {:.3e} kg·m²/s ({:.3e} of Σ |r×mv|+|Iω|)",
        d.angular_momentum,
        rel(d.angular_momentum, d.angular_momentum_scale)
    );
    println!("    barycenter          {:.3e} m (from Rc(0) + P(0) t / M)", d.barycenter);
    if d.locks > 0 {
        println!(
            "    locked directions   {} held within {:.3e} m and {:.3e} rad of their initial values",
            d.locks, d.locked_translation, d.locked_rotation
        );
        // Engaged locks, a hinge's at one instant on one line: "h1 x, y, rz at t = 0.1 s".
        let engaged: Vec<String> = r
            .lock_engagements
            .chunk_by(|a, b| a.0.hinge == b.0.hinge && a.1 == b.1)
            .map(|g| {
                let dirs: Vec<&str> = g.iter().map(|(l, _)| DIRECTION_NAMES[l.direction]).collect();
                format!("{} {} at t = {:.6} s", scenario.model.hinges[g[0].0.hinge].name, dirs.join(", "), g[0].1)
            })
            .collect();
        let (n, all) = (r.lock_engagements.len(), d.locks);
        let rest = if n < all {
            format!("; the other {} carried none and were never solved for", all - n)
        } else {
            String::new()
        };
        if n == 0 {
            println!("    locks engaged       none of {all}: no lock carried load, none was solved for");
        } else {
            let more = if engaged.len() > 4 { format!("; and {} more", engaged.len() - 4) } else { String::new() };
            println!(
                "    locks engaged       {n} of {all} (carrying load{rest}): {}{more}",
                engaged[..engaged.len().min(4)].join("; ")
            );
        }
    }
    let e_rel = rel(d.energy, d.energy_initial.abs());
    let scale = d.energy_initial.abs().max(d.dissipated.abs());
    if r.energy_conserving {
        println!("    energy E = T + V    {:.3e} J ({:.3e} relative; conserved by these laws)", d.energy, e_rel);
    } else {
        println!(
            "    energy E = T + V    {:.3e} J max change ({:.3e} relative), {:+.3e} J at the end: not conserved by these laws (damping, hysteresis, stops, a 2-D table, or the paper-linear law of docs/model.md §4)",
            d.energy, e_rel, d.energy_final_change
        );
        println!(
            "    dissipated by hinges D  {:.6e} J by the end (damping, hysteresis, stops; for the paper-linear law the work of its non-potential torque)",
            d.dissipated
        );
        println!(
            "    balance |Δ(E + D)|      {:.3e} J ({:.3e} relative)",
            d.energy_balance,
            rel(d.energy_balance, scale)
        );
    }
    if let Some(t) = r.released_at {
        println!("  restraint        released at t = {t:.4} s");
    }
    if let Some(t) = r.deployed_90 {
        println!("  deployment       90 % of the design radius at t = {t:.4} s");
    }
    if !r.events.is_empty() || r.branch_events > 0 {
        println!(
            "  hinge events: {} located ({} stop or latch, {} hysteresis branch changes or table points)",
            r.events.len() + r.branch_events,
            r.events.len(),
            r.branch_events
        );
    }
    for e in &r.events {
        let h = &scenario.model.hinges[e.hinge];
        println!("    t = {:.9} s  {}: {}", e.t, h.name, e.description);
    }
    for (i, e) in r.events.iter().enumerate() {
        let first_latch = r.events[..i].iter().all(|p| p.hinge != e.hinge || p.kind != EventKind::Latch);
        if e.kind == EventKind::Latch && first_latch {
            let total = r.hinge_dissipated.get(e.hinge).copied().unwrap_or(0.0);
            println!(
                "    energy lost at and after latching, hinge {}: {:.6e} J (dissipated from t = {:.6} s to the end)",
                scenario.model.hinges[e.hinge].name,
                total - e.hinge_dissipated,
                e.t
            );
        }
    }
}
