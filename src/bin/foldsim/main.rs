//! `foldsim`: command-line front end of the foldsim library. One file per command:
//! `args.rs` (what the command line takes), `run.rs` (`run`, with the animation and page
//! targets), `report.rs` (the end-of-run report), `view.rs` (`animate`, `view`),
//! `generate.rs` (`generate`), `sweep.rs` (`sweep`), `modes.rs` (`modes`, `equilibrium`),
//! `export.rs` (`export fmu`), `overlaps.rs` (`overlaps`).

#[macro_use]
mod out;
mod args;
mod export;
mod fit;
mod generate;
mod modes;
mod overlaps;
mod report;
mod run;
mod sweep;
#[cfg(feature = "animation")]
mod view;
mod watch;

use args::{Cli, Command, Shape};
use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        #[cfg(feature = "animation")]
        Command::Run {
            scenario,
            csv,
            columns,
            large_output,
            contacts,
            events,
            quiet,
            animation,
            animation_fps,
            view: page,
        } => {
            let animation_target = animation.map(|path| (path, animation_fps));
            let page_target = page.as_deref().map(|p| (p, animation_fps));
            run::run(&scenario, (csv, contacts, events), columns, large_output, quiet, animation_target, page_target)
                .and_then(|(csv, frames)| match (page, frames) {
                    (Some(page), Some(frames)) => view::view_run(&scenario, &csv, &page, frames, quiet),
                    _ => Ok(()),
                })
        }
        #[cfg(not(feature = "animation"))]
        Command::Run { scenario, csv, columns, large_output, contacts, events, quiet } => {
            run::run(&scenario, (csv, contacts, events), columns, large_output, quiet, None, None).map(|_| ())
        }
        #[cfg(feature = "animation")]
        Command::Animate { scenario, csv, output, fps } => view::animate(&scenario, &csv, &output, fps),
        #[cfg(feature = "animation")]
        Command::View { scenario, csv, output, columns, fps } => view::view(&scenario, &csv, &output, fps, &columns),
        Command::Sweep { scenario, output, workers, runs, seed, quiet } => {
            sweep::sweep(&scenario, output, workers, runs, seed, quiet)
        }
        #[cfg(feature = "plot")]
        Command::Fit { scenario, data, law, moment, direction, free, sigma, output, plot, max_iterations, quiet } => {
            let what = fit::What { scenario, data, law, moment, direction };
            fit::fit(what, (&free, &sigma), (output, plot), max_iterations, quiet)
        }
        #[cfg(not(feature = "plot"))]
        Command::Fit { scenario, data, law, moment, direction, free, sigma, output, max_iterations, quiet } => {
            let what = fit::What { scenario, data, law, moment, direction };
            fit::fit(what, (&free, &sigma), (output, None), max_iterations, quiet)
        }
        Command::Modes { scenario, output, state, spin_rate: Some(w), quiet, .. } => {
            let choice = modes::Choice { at: state.at, deployed: state.deployed, count: None };
            modes::spinning_modes(&scenario, output, choice, w, quiet)
        }
        Command::Modes { scenario, output, state, count, view, mode, quiet, spin_rate: None } => modes::modes(
            &scenario,
            output,
            modes::Choice { at: state.at, deployed: state.deployed, count },
            (view, &mode),
            quiet,
        ),
        Command::Linearize { scenario, output, state, inputs, outputs, modes: reduced, hub_held, quiet } => {
            let choice = modes::Choice { at: state.at, deployed: state.deployed, count: reduced };
            modes::linearize(&scenario, output, choice, (inputs, outputs), hub_held, quiet)
        }
        Command::Export { what: args::Export::Fmu { scenario, output, outputs, inputs, parameters, library } } => {
            let request = foldsim::export::fmu::Request {
                outputs: outputs.unwrap_or_default(),
                inputs: inputs.unwrap_or_default(),
                parameters: parameters.map(|p| if p == ["none"] { Vec::new() } else { p }),
            };
            export::fmu(&scenario, &output, &request, library)
        }
        Command::Equilibrium { scenario, output, tolerance, spin_rate, quiet } => {
            modes::equilibrium(&scenario, output, tolerance, spin_rate, quiet)
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
                    let duration = duration.unwrap_or(foldsim::generate::options::FlasherOptions::default().duration);
                    generate::generate_flasher(&args, k_translation, k_bending, k_fold, (duration, tolerance), output)
                }
            } else {
                let defaults = foldsim::generate::Params::default();
                let p = foldsim::generate::Params {
                    panel_mass: panel_mass.unwrap_or(defaults.panel_mass),
                    k_translation,
                    k_bending,
                    k_fold,
                    fold_deg: fold_deg.unwrap_or(defaults.fold_deg),
                    duration: duration.unwrap_or(defaults.duration),
                    tolerance: tolerance.unwrap_or(defaults.tolerance),
                    ..defaults
                };
                generate::generate(shape, &p, output)
            }
        }
        Command::Overlaps { scenario, csv, sharp, pairs, fail_above, quiet } => {
            overlaps::overlaps(&scenario, &csv, sharp, pairs, fail_above, quiet)
        }
        #[cfg(feature = "plot")]
        Command::Plot { csv, columns, degrees, title, output } => {
            foldsim::output::plot::plot_columns(&csv, &columns, degrees, &title, &output)
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) if out::is_broken_pipe(&message) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}
