//! The command line's commands and options (clap).

use clap::{Parser, Subcommand};
use foldsim::generate::Params;
use foldsim::generate::options::FlasherOptions;
use std::path::PathBuf;

#[derive(Parser)]
#[command(
    name = "foldsim",
    version,
    about = "Deployment dynamics of folded spacecraft structures with flexible hinges"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand)]
pub enum Command {
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
        /// Also write the contact event log (CSV): every episode of every body pair, with its
        /// start, end, impact speed, deepest penetration and peak force, resting contact of
        /// the stowed package told apart from impacts (docs/contact.md).
        #[arg(long)]
        contacts: Option<PathBuf>,
        /// Also write every located hinge event (CSV): time, hinge, kind (a stop hit or left,
        /// a latch), the law's description and the hinge's dissipated energy so far; the
        /// report lists the first few (docs/outputs.md).
        #[arg(long)]
        events: Option<PathBuf>,
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
    /// Fit scenario values to measurements (docs/fit.md): the values named by --free (key
    /// paths, as sweeps name them) chosen so that the run's output columns match DATA's, by
    /// bounded Levenberg–Marquardt; prints the fitted values with standard errors,
    /// correlations and warnings, and writes the fitted scenario with -o.
    #[command(group(clap::ArgGroup::new("what").required(true).args(["scenario", "law"])))]
    Fit {
        /// Scenario file (TOML): the free values start from its values.
        scenario: Option<PathBuf>,
        /// Measurements (CSV) for a scenario: a `t` column (s) and output columns by name
        /// (h1_yaw, deployed, …); an empty cell is a value not measured then.
        #[arg(long, requires = "scenario", conflicts_with = "law")]
        data: Option<PathBuf>,
        /// A hinge law on its own (a TOML file with `law = { … }`, as a hinge's), fitted to a
        /// bench test given by --moment instead of a scenario's run.
        #[arg(long, requires = "moment")]
        law: Option<PathBuf>,
        /// The bench test for --law (CSV): angle_deg,moment_Nm (or angle_rad,moment_Nm, or
        /// displacement_m,force_N), the points in the order taken (loading, then unloading).
        #[arg(long, requires = "law")]
        moment: Option<PathBuf>,
        /// The law's direction the bench test drives (x, y, z, rx, ry, rz).
        #[arg(long, default_value = "rz", requires = "law")]
        direction: String,
        /// A value to fit, KEY or KEY=LOW:HIGH (either bound may be empty); repeat for more.
        /// A wildcard (hinge.*.law.k_theta) ties one value across every entry it matches.
        #[arg(long = "free", required = true)]
        free: Vec<String>,
        /// A column's measurement noise, COLUMN=SIGMA in its unit (its residuals are divided
        /// by it); repeat for more. Columns without one weigh 1 in their own unit.
        #[arg(long = "sigma")]
        sigma: Vec<String>,
        /// The scenario (or law file) with the fitted values, to write (never over an input).
        #[arg(long, short)]
        output: Option<PathBuf>,
        /// A PNG of the data against the fitted run.
        #[cfg(feature = "plot")]
        #[arg(long)]
        plot: Option<PathBuf>,
        /// Most Levenberg–Marquardt iterations.
        #[arg(long, default_value_t = 100)]
        max_iterations: usize,
        /// Print nothing but the result and errors.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Natural modes of a structure at rest (docs/linear.md): free-free and with the hub held,
    /// frequencies, damping ratios and the hub-fixed modes' effective masses and inertias
    /// about the hub, as a CSV table.
    Modes {
        /// Scenario file (TOML; see docs/scenario.md).
        scenario: PathBuf,
        /// The table to write (CSV). Default: `<scenario name>-modes.csv` in the current
        /// directory.
        #[arg(long, short)]
        output: Option<PathBuf>,
        #[command(flatten)]
        state: LinearState,
        /// Only the N lowest flexible modes (free-free and hub-fixed), by the sparse
        /// shift-invert Lanczos solver (docs/linear.md). Default: every mode by the dense
        /// solver up to 200 bodies, the 20 lowest by Lanczos above.
        #[arg(long)]
        count: Option<usize>,
        /// The modes of the structure spinning steadily at this rate (rad/s) about the hub's
        /// z axis: its relative equilibrium near the state, then the state matrix's
        /// eigenvalues in the turning frame (gyroscopic coupling, centrifugal stiffening).
        #[arg(long, allow_negative_numbers = true, conflicts_with_all = ["count", "view"])]
        spin_rate: Option<f64>,
        /// Also write a viewer page (HTML) that animates one mode shape over two periods.
        #[arg(long)]
        view: Option<PathBuf>,
        /// The mode the page animates: `free:K` or `hub_fixed:K`, K the table's `index`
        /// (default `free:6`, the first flexible free-free mode).
        #[arg(long, default_value = "free:6", requires = "view")]
        mode: String,
        /// Print nothing but errors.
        #[arg(long, short)]
        quiet: bool,
    },
    /// The linear state-space model `ẋ = A x + B u`, `y = C x + D u` of a structure about a
    /// state (docs/linear.md), as NumPy's `.npz` (A, B, C, D, y0 and the names of states,
    /// inputs and outputs) for python-control's `control.ss(A, B, C, D)`.
    Linearize {
        /// Scenario file (TOML; see docs/scenario.md).
        scenario: PathBuf,
        /// The model to write (`.npz`). Default: `<scenario name>-linear.npz` in the current
        /// directory.
        #[arg(long, short)]
        output: Option<PathBuf>,
        #[command(flatten)]
        state: LinearState,
        /// Bodies that take force and torque inputs (their own frames, at their centres of
        /// mass), by name, comma-separated. Default: the hub.
        #[arg(long, value_delimiter = ',')]
        inputs: Option<Vec<String>>,
        /// Outputs: output column names or patterns (`*`), comma-separated, among those the
        /// linear model offers (docs/linear.md). Default: the hub's MRPs and rates.
        #[arg(long, value_delimiter = ',')]
        outputs: Option<Vec<String>>,
        /// A reduced model: the six rigid-body modes and the N lowest flexible free-free modes
        /// as modal coordinates (with --hub-held: the hub's six coordinates and the N lowest
        /// modes with the hub held), the rigid-body poles exactly at zero (docs/linear.md).
        /// About a state at rest only.
        #[arg(long)]
        modes: Option<usize>,
        /// With --modes: the hub as a rigid body and the modes with the hub held (hybrid
        /// coordinates) instead of the free-free modes.
        #[arg(long, requires = "modes")]
        hub_held: bool,
        /// Print nothing but errors.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Static equilibrium of a structure (docs/linear.md): the configuration nearest its
    /// initial state where every hinge's wrench balances, the hub held; written as the
    /// `[initial]` tables a scenario takes.
    Equilibrium {
        /// Scenario file (TOML; see docs/scenario.md).
        scenario: PathBuf,
        /// The `[initial]` tables to write (TOML). Default: `<scenario name>-equilibrium.toml`
        /// in the current directory.
        #[arg(long, short)]
        output: Option<PathBuf>,
        /// The largest force (N) or torque (N·m) left on a body.
        #[arg(long, default_value_t = 1e-10)]
        tolerance: f64,
        /// Find the relative equilibrium of the structure spinning steadily at this rate
        /// (rad/s) about the hub's z axis through its centre of mass (centrifugal stiffening,
        /// every hinge stretched by it); the tables then start the hub at that rate.
        #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
        spin_rate: f64,
        /// Print nothing but errors.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Export a scenario for another tool: `foldsim export fmu` writes an FMI 2.0
    /// co-simulation FMU (docs/interop.md).
    Export {
        #[command(subcommand)]
        what: Export,
    },
    /// Write a generated structure as a scenario file.
    #[command(allow_negative_numbers = true)]
    Generate {
        #[command(subcommand)]
        shape: Shape,
        /// Panel mass, kg (z-fold and grid; default 2).
        #[arg(long, global = true)]
        panel_mass: Option<f64>,
        /// Hinge translational stiffness, N/m.
        #[arg(long, default_value_t = Params::default().k_translation, global = true)]
        k_translation: f64,
        /// Hinge stiffness of the two rotations off the fold axis, N·m/rad.
        #[arg(long, default_value_t = Params::default().k_bending, global = true)]
        k_bending: f64,
        /// Hinge fold stiffness, N·m/rad.
        #[arg(long, default_value_t = Params::default().k_fold, global = true)]
        k_fold: f64,
        /// Stowed fold angle (z-fold) or initial hub-hinge fold (grid), degrees (default 30).
        #[arg(long, global = true)]
        fold_deg: Option<f64>,
        /// Simulated time, s (default: 10 for a z-fold or grid, 5 for a flasher).
        #[arg(long, global = true)]
        duration: Option<f64>,
        /// Integrator tolerance (rtol = atol). Default 1e-8; a flasher with --thickness (in
        /// contact) 1e-5.
        #[arg(long, global = true)]
        tolerance: Option<f64>,
        /// Scenario file to write.
        #[arg(long, short, global = true)]
        output: Option<PathBuf>,
    },
    /// How deep any two bodies overlap over a finished run, measured from its CSV's poses
    /// alone, apart from the contact code (parry's GJK/EPA on each body's solid;
    /// docs/contact.md §3): the deepest pairs, each against the thinner body's thickness.
    Overlaps {
        /// The run's scenario file.
        scenario: PathBuf,
        /// The run's CSV (with every body's _R_x/y/z and _q_w/x/y/z columns).
        #[arg(long)]
        csv: PathBuf,
        /// Take thin plates as sharp prisms (by default as the contact code's samples describe
        /// them: flat faces, the rim rounded with half the thickness).
        #[arg(long)]
        sharp: bool,
        /// How many pairs to list, deepest first.
        #[arg(long, default_value_t = 5)]
        pairs: usize,
        /// Fail (exit status 1) if a pair overlaps deeper than this fraction of the thinner
        /// body's thickness (0.1: ten per cent).
        #[arg(long)]
        fail_above: Option<f64>,
        /// No progress lines.
        #[arg(long)]
        quiet: bool,
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
pub enum Shape {
    /// A z-folded chain of panels off the hub.
    #[command(allow_negative_numbers = true)]
    Zfold {
        /// Number of panels.
        #[arg(long)]
        panels: usize,
    },
    /// A grid of panels hinged to their neighbours (many loops).
    #[command(allow_negative_numbers = true)]
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
pub struct FlasherArgs {
    /// Number of gores N (sides of the hub), ≥ 3.
    #[arg(long)]
    pub gores: usize,
    /// Rings of panels (nodes per major fold − 1), ≥ 1.
    #[arg(long)]
    pub rings: usize,
    /// Hub circumradius, m.
    #[arg(long, default_value_t = FlasherOptions::default().hub_radius)]
    pub hub_radius: f64,
    /// Panel thickness, m (mass properties and shapes); above 0 the panels are stowed in nested
    /// layers with a [contact] table (triangles and quads; docs/flasher.md, Thick panels).
    #[arg(long, default_value_t = FlasherOptions::default().thickness)]
    pub thickness: f64,
    /// Mass per unit area of the panels, kg/m².
    #[arg(long, default_value_t = FlasherOptions::default().areal_density)]
    pub areal_density: f64,
    /// Hub mass, kg.
    #[arg(long, default_value_t = FlasherOptions::default().hub_mass)]
    pub hub_mass: f64,
    /// Hub principal inertia about its centroid (x, y in its plane, z its axis), kg·m²,
    /// comma-separated. Default: a uniform disc of the hub's radius and mass.
    #[arg(long, value_delimiter = ',')]
    pub hub_inertia: Option<Vec<f64>>,
    /// Panel model: quads (rigid, flat in both states), ring-quads (one ring each, strained
    /// when stowed) or triangles (a bending hinge on each quad's diagonal).
    #[arg(long, default_value = "triangles", value_parser = ["triangles", "quads", "ring-quads"])]
    pub panels: String,
    /// Where the hinges' fold axes lie with thick panels: shifted (each moved across its crease
    /// onto the line about which the stowed fold is a pure turn, so neither the stowed wrap
    /// nor the deployed sheet strains the hinges) or mid-plane (on the crease, the hinges
    /// stretched by the layers' offsets when stowed). docs/flasher.md, Thick panels.
    #[arg(long, default_value = "shifted", value_parser = ["shifted", "mid-plane"])]
    pub hinge_axes: String,
    /// Fold damping of the creases, N·m·s/rad [default: 0.05; 1 with --thickness, as hardware
    /// deploys through damped hinges (docs/flasher.md, Damped folds)].
    #[arg(long)]
    pub c_fold: Option<f64>,
    /// Bending stiffness of the diagonal hinges (triangle model), N·m/rad.
    #[arg(long, default_value_t = FlasherOptions::default().laws.k_bending)]
    pub k_panel_bending: f64,
    /// Bending damping of the diagonal hinges (triangle model), N·m·s/rad.
    #[arg(long, default_value_t = FlasherOptions::default().laws.c_bending)]
    pub c_panel_bending: f64,
    /// Translational damping of every hinge, N·s/m.
    #[arg(long, default_value_t = FlasherOptions::default().laws.c_translation)]
    pub c_translation: f64,
    /// Damping of every hinge's two rotations off its fold axis, N·m·s/rad.
    #[arg(long, default_value_t = FlasherOptions::default().laws.c_rotation)]
    pub c_rotation: f64,
    /// Thick panels (axes shifted): stiffness of each folding crease's stop at flat, where
    /// its panels' edges meet, N·m/rad (0: no stops); damped for the contact's restitution.
    #[arg(long, default_value_t = FlasherOptions::default().laws.k_stop)]
    pub k_stop: f64,
    /// Thick panels (axes shifted): bending stiffness per unit length of the membrane that
    /// bonds each folding crease's panels (a membrane hinge: the panels' edges move across the
    /// fold line, resisted by its bending, until it is taut), N·m; the default is a 125-µm
    /// polyimide film; 0: no membrane (each crease a pin on its axis). docs/flasher.md,
    /// Membrane hinges.
    #[arg(long, default_value_t = FlasherOptions::default().laws.membrane_bending)]
    pub membrane_bending: f64,
    /// Thick panels: the membrane's width across the fold line, m (how far the panels' edges
    /// move across it, each way, before it is taut). Default: 5 panel thicknesses.
    #[arg(long)]
    pub membrane_width: Option<f64>,
    /// Thick panels: damping ratio of the panels' motion across a fold line while its membrane
    /// is slack, on the two panels' reduced mass (a modelling choice, not a measured value).
    #[arg(long, default_value_t = FlasherOptions::default().laws.membrane_damping_ratio)]
    pub membrane_damping_ratio: f64,
    /// Initial hub spin about its axis, rev/min.
    #[arg(long, default_value_t = FlasherOptions::default().spin_rpm)]
    pub spin_rpm: f64,
    /// Hold the stowed state until this time, s (run.release_at).
    #[arg(long)]
    pub release_at: Option<f64>,
    /// Output step, s (default: duration / 1000).
    #[arg(long)]
    pub output_step: Option<f64>,
    /// Integrator: dop853, sdirk4 (stiff hinges on many panels) or auto (DOP853, switching
    /// to SDIRK4 where stiffness holds it back). Default dop853; with --thickness (panels in
    /// contact) sdirk4.
    #[arg(long, value_parser = ["dop853", "sdirk4", "auto"])]
    pub integrator: Option<String>,
    /// Print every hinge's stowed fold angle, not only the distinct ones.
    #[arg(long)]
    pub all_folds: bool,
    /// Skip the trial run that projects the run's wall time (with thick panels it runs until
    /// the packed start opens and two seconds more: tens of seconds for large flashers).
    #[arg(long)]
    pub no_trial: bool,
}

/// Where `modes` and `linearize` take the structure's state.
#[derive(clap::Args, Debug, Clone, Copy)]
pub(crate) struct LinearState {
    /// Run the scenario to this time (s) first and take the state there (default: its
    /// initial state).
    #[arg(long, default_value_t = 0.0)]
    pub(crate) at: f64,
    /// Take the design state instead (every tree hinge's δ and angles zero, every body at
    /// rest, the hub where the scenario starts it): the deployed structure of a generated
    /// flasher or z-fold, stress-free, an equilibrium.
    #[arg(long, conflicts_with = "at")]
    pub(crate) deployed: bool,
}

/// What `foldsim export` writes.
#[derive(Subcommand, Debug)]
pub enum Export {
    /// An FMI 2.0 co-simulation FMU of a scenario (Linux x86_64): foldsim's own integrator
    /// steps between communication points; inputs, outputs and parameters by name
    /// (docs/interop.md).
    Fmu {
        /// Scenario file (TOML; see docs/scenario.md).
        scenario: PathBuf,
        /// The FMU to write (.fmu); its name is the model identifier.
        #[arg(short, long)]
        output: PathBuf,
        /// Outputs: output column names or patterns (`*`, `?`, `default`), comma-separated.
        /// Default: the default set (docs/outputs.md).
        #[arg(long, value_delimiter = ',')]
        outputs: Option<Vec<String>>,
        /// Inputs, comma-separated: a body's name (its six inputs `<body>_F_x` … `_T_z`, its
        /// own frame), a motor's (`<motor>_effort`), an actuator's (`<actuator>_torque`),
        /// `actuators` (every one), or an input's own name. Default: the hub.
        #[arg(long, value_delimiter = ',')]
        inputs: Option<Vec<String>>,
        /// Parameters: key-path patterns (`hinge.*.law.*`), comma-separated, among the
        /// numbers the scenario writes outside [run]; `none` for no parameters. Default: all.
        #[arg(long, value_delimiter = ',')]
        parameters: Option<Vec<String>>,
        /// The FMU's shared library (default: `libfoldsim_fmu.so` beside this program, as
        /// `cargo build --release` leaves it).
        #[arg(long)]
        library: Option<PathBuf>,
    },
}
