//! `impact` command line: run a scene with DGMPM, MPM and FEM side by side, and check
//! that DGMPM captures the wave front more sharply than MPM. The commands are in `cli/`.
use clap::Parser;

mod cli;

fn main() {
    let cli = cli::Cli::parse();
    // MPI when launched by mpirun/srun with the `mpi` feature (finalised before exiting)
    let ranks = impact::ranks::init().unwrap_or_else(|e| {
        eprintln!("error: {e}");
        std::process::exit(2);
    });
    if let Err(e) = impact::interrupt::install() {
        eprintln!("error: cannot install the SIGINT/SIGTERM handlers: {e}");
        std::process::exit(2);
    }
    let result = cli::dispatch(&cli.command);
    match result {
        Ok(true) => {}
        Ok(false) => {
            drop(ranks);
            std::process::exit(1)
        }
        Err(e) => {
            // every rank fails alike (inputs and blow-ups are seen by all): one message
            if impact::ranks::is_root() {
                eprintln!("error: {e:#}");
            }
            // exit codes: 0 done or the gate passes, 1 the gate fails, 2 bad input,
            // 3 a run blew up (its frames kept), 130 interrupted
            let code = if e.downcast_ref::<impact::interrupt::Interrupted>().is_some() {
                130
            } else if e.downcast_ref::<impact::run::BlewUp>().is_some() {
                3
            } else {
                2
            };
            drop(ranks);
            std::process::exit(code);
        }
    }
}
