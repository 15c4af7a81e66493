//! Fuzz target `machine`: any bytes read as a machine file (`--machine FILE.toml`) give a
//! machine or an error naming the file — never a panic — and a machine that is read carries
//! G-code and APT CL programs with rotary moves through its kinematics without panicking.
//! Run with `cargo +nightly fuzz run machine` from `crates/swarf-path`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use swarf_path::kinematics::Machine;
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::summary::summarize;

/// Rotary words on every axis a machine may have, linear and circular moves between them.
const GCODE: &str = "G21 G90\nG0 X0 Y0 Z10 A0 B0 C0\nG1 X10 Y5 Z-1 A30 B-20 C90 F500\n\
                     G2 X20 Y5 I5 J0\nG1 A-45 B45 C-180\nG93 G1 X0 Y0 Z5 A10 B10 C10 F2\nM2\n";
const APT: &str = "CUTTER/10,2\nFEDRAT/1000\nGOTO/0,0,10,0,0,1\nGOTO/10,5,0,0.3,0.2,0.93\n\
                   GOTO/20,5,0,-0.5,0,0.866\nGOTO/20,5,0,0,0,-1\nFINI\n";

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(machine) = Machine::from_toml(&text, "fuzz.toml", "fuzz") {
        for (program, file) in [(GCODE, "fuzz.ngc"), (APT, "fuzz.apt")] {
            if let Ok(p) = read_program_str(program, file, machine.clone(), &ReadOptions::default())
            {
                let _ = summarize(&p);
            }
        }
    }
});
