//! Prints canonical events in the exact form of LinuxCNC's interpreter tests, so swarf's G-code
//! reading can be diffed line by line against LinuxCNC's `.expected` files.
//!
//! Each motion call is one line, prefixed with ` N..... ` as the tests print it (they mask the
//! line numbers), values in program units (the printer follows [`Canon::Units`]: inch
//! programs print inches) with four decimals, like the C `%.4f`:
//!
//! ```text
//!  N..... STRAIGHT_TRAVERSE(1.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
//!  N..... STRAIGHT_FEED(1.0000, 1.0000, -1.0000, 0.0000, 0.0000, 0.0000)
//!  N..... ARC_FEED(0.0000, 1.0000, 0.0000, 0.0000, 1, 0.0000, 0.0000, 0.0000, 0.0000)
//! ```
//!
//! `ARC_FEED(first_end, second_end, first_axis, second_axis, rotation, axis_end_point, a, b, c)`
//! uses LinuxCNC's plane order: X,Y about Z for G17; Z,X about Y for G18; Y,Z about X for G19.
//! Splines print as rs274 prints them: `NURBS_FEED(n, ...)`, n the number of control points
//! with the start (4 for G5, 3 for G5.1, a G5.2 … G5.3 block's points and its start), the
//! three dots as they are.
//! A G33.1 rigid tap prints as rs274 prints it: `RIGID_TAP(x, y, z)`, the bottom of the tap,
//! and not the moves that make it.
//! An arc about an axis that is none of X, Y, Z (an APT `CIRCLE/` in a tilted plane), which
//! LinuxCNC cannot make, prints as swarf's own
//! `ARC_FEED_AXIS(x, y, z, centre x, y, z, normal i, j, k, turns)` (counter-clockwise about the
//! normal), so no motion is left out of the print.
//! The motion calls and the operator messages (`MESSAGE("…")` for `(MSG,…)` and `(DEBUG,…)`)
//! are printed; the other canonical calls (units, offsets, feeds, comments) differ in detail
//! between LinuxCNC versions and are not needed to compare paths.

use std::io::{self, Write};

use crate::{Canon, CanonSink, MessageKind, Units, Warning};

/// A [`CanonSink`] that writes LinuxCNC canonical motion calls to `W`.
///
/// Write errors do not stop the reader (a sink cannot fail); the first one is kept and later
/// writes are skipped. Check [`CanonicalPrinter::io_error`] or use
/// [`CanonicalPrinter::finish`].
#[derive(Debug)]
pub struct CanonicalPrinter<W: Write> {
    out: W,
    units: Units,
    error: Option<io::Error>,
    /// The reader's warnings, kept for the caller (they are no canonical call).
    warnings: Vec<Warning>,
    /// The program's motion built on a machine, when one is given: it re-expresses the position
    /// where tool centre point control turns on or off, as the simulation does, and the reader
    /// takes it back ([`CanonSink::position`]).
    tracker: Option<crate::builder::MoveBuilder>,
    /// Inside a G33.1 rigid tap, printed as rs274's one `RIGID_TAP(x, y, z)`: its moves are
    /// not printed until the feed mode is restored.
    in_rigid_tap: bool,
}

impl<W: Write> CanonicalPrinter<W> {
    /// A printer writing to `out`, starting in millimetres (as LinuxCNC's canon does).
    pub fn new(out: W) -> Self {
        Self {
            out,
            units: Units::Mm,
            error: None,
            warnings: Vec::new(),
            tracker: None,
            in_rigid_tap: false,
        }
    }

    /// Prints the calls as a program runs on `machine` (file name `file`): after a program turns
    /// tool centre point control on or off, the axes a block leaves out are where the machine
    /// is, as `swarf simulate` moves them. (Without it, the program's own coordinates.)
    pub fn with_machine(mut self, machine: crate::kinematics::Machine, file: &str) -> Self {
        self.tracker = Some(crate::builder::MoveBuilder::new(machine, file));
        self
    }

    /// The warnings the reader gave so far.
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    /// The first write error, if any.
    pub fn io_error(&self) -> Option<&io::Error> {
        self.error.as_ref()
    }

    /// Flushes and returns the writer, or the first write error.
    ///
    /// # Errors
    /// The first error met while writing or flushing.
    pub fn finish(mut self) -> io::Result<W> {
        if let Some(e) = self.error.take() {
            return Err(e);
        }
        self.out.flush()?;
        Ok(self.out)
    }

    /// Program units from mm for linear axes.
    fn u(&self, mm: f64) -> f64 {
        match self.units {
            Units::Mm => mm,
            Units::Inch => mm / 25.4,
        }
    }

    fn write_event(&mut self, event: &Canon<'_>) -> io::Result<()> {
        if self.in_rigid_tap {
            match event {
                Canon::Units(u) => self.units = *u,
                Canon::FeedMode(m) if *m != crate::FeedMode::SpindleSynchronised => {
                    self.in_rigid_tap = false
                }
                _ => {}
            }
            return Ok(());
        }
        match event {
            Canon::Units(u) => self.units = *u,
            // rs274 prints the tap's bottom, X Y Z, and not the moves that make it.
            Canon::RigidTap { end } => {
                self.in_rigid_tap = true;
                writeln!(
                    self.out,
                    " N..... RIGID_TAP({:.4}, {:.4}, {:.4})",
                    self.u(end.x),
                    self.u(end.y),
                    self.u(end.z)
                )?;
            }
            Canon::Traverse { end } | Canon::Feed { end } => {
                let name = if matches!(event, Canon::Traverse { .. }) {
                    "STRAIGHT_TRAVERSE"
                } else {
                    "STRAIGHT_FEED"
                };
                writeln!(
                    self.out,
                    " N..... {name}({:.4}, {:.4}, {:.4}, {:.4}, {:.4}, {:.4})",
                    self.u(end.x),
                    self.u(end.y),
                    self.u(end.z),
                    end.a,
                    end.b,
                    end.c
                )?;
            }
            Canon::Arc {
                end,
                center,
                rotation,
                plane,
            } => {
                let (f, s, n) = plane.axes();
                let e = end.to_array();
                writeln!(
                    self.out,
                    " N..... ARC_FEED({:.4}, {:.4}, {:.4}, {:.4}, {}, {:.4}, {:.4}, {:.4}, {:.4})",
                    self.u(e[f]),
                    self.u(e[s]),
                    self.u(center[0]),
                    self.u(center[1]),
                    rotation,
                    self.u(e[n]),
                    end.a,
                    end.b,
                    end.c
                )?;
            }
            Canon::ArcAxis {
                end,
                center,
                normal,
                turns,
            } => {
                writeln!(
                    self.out,
                    " N..... ARC_FEED_AXIS({:.4}, {:.4}, {:.4}, {:.4}, {:.4}, {:.4}, {:.6}, {:.6}, \
                     {:.6}, {turns})",
                    self.u(end.x),
                    self.u(end.y),
                    self.u(end.z),
                    self.u(center[0]),
                    self.u(center[1]),
                    self.u(center[2]),
                    normal[0],
                    normal[1],
                    normal[2],
                )?;
            }
            // rs274 prints a spline as its number of control points, the start included (4
            // for G5, 3 for G5.1, the points of a G5.2 … G5.3 block and its start), and no
            // numbers: `NURBS_FEED(4, ...)`.
            Canon::Spline { controls, .. } => {
                writeln!(self.out, " N..... NURBS_FEED({}, ...)", controls.len() + 1)?
            }
            Canon::Message {
                kind: MessageKind::Msg | MessageKind::Debug,
                text,
            } => writeln!(self.out, " N..... MESSAGE(\"{text}\")")?,
            // `(print,…)`: rs274 writes the text itself among the calls.
            Canon::Message {
                kind: MessageKind::Print,
                text,
            } => writeln!(self.out, "{text}")?,
            _ => {}
        }
        Ok(())
    }
}

impl<W: Write> CanonSink for CanonicalPrinter<W> {
    fn emit(&mut self, line: u32, event: &Canon<'_>) {
        if let Some(t) = &mut self.tracker {
            t.emit(line, event);
            // (Only the position matters here: the moves are dropped as they come.)
            t.take_moves().for_each(drop);
        }
        if self.error.is_some() {
            // Keep following the units so a later reader of the state is not confused, but
            // write nothing more after a failure.
            if let Canon::Units(u) = event {
                self.units = *u;
            }
            return;
        }
        if let Err(e) = self.write_event(event) {
            self.error = Some(e);
        }
    }

    fn warn(&mut self, warning: Warning) {
        self.warnings.push(warning);
    }

    fn position(&self) -> Option<crate::Axes> {
        self.tracker.as_ref().and_then(CanonSink::position)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Axes, Plane};

    #[test]
    fn an_arc_about_a_tilted_axis_is_printed_too() {
        let mut p = CanonicalPrinter::new(Vec::new());
        p.emit(
            1,
            &Canon::ArcAxis {
                end: Axes {
                    y: 20.0,
                    ..Axes::default()
                },
                center: [0.0, 15.0, 0.0],
                normal: [0.6, 0.0, 0.8],
                turns: 1,
            },
        );
        let out = String::from_utf8(p.finish().unwrap()).unwrap();
        assert_eq!(
            out,
            " N..... ARC_FEED_AXIS(0.0000, 20.0000, 0.0000, 0.0000, 15.0000, 0.0000, 0.600000, \
             0.000000, 0.800000, 1)\n"
        );
    }

    #[test]
    fn prints_linuxcnc_form() {
        let mut p = CanonicalPrinter::new(Vec::new());
        p.emit(1, &Canon::Units(Units::Inch));
        p.emit(
            2,
            &Canon::Traverse {
                end: Axes {
                    x: 25.4,
                    y: -0.0,
                    z: 50.8,
                    a: 90.0,
                    ..Axes::default()
                },
            },
        );
        p.emit(
            3,
            &Canon::Arc {
                end: Axes {
                    x: 25.4,
                    y: 0.0,
                    z: 2.54,
                    ..Axes::default()
                },
                center: [12.7, 0.0],
                rotation: -2,
                plane: Plane::XZ,
            },
        );
        let s = String::from_utf8(p.finish().unwrap()).unwrap();
        assert_eq!(
            s,
            " N..... STRAIGHT_TRAVERSE(1.0000, -0.0000, 2.0000, 90.0000, 0.0000, 0.0000)\n \
             N..... ARC_FEED(0.1000, 1.0000, 0.5000, 0.0000, -2, 0.0000, 0.0000, 0.0000, 0.0000)\n"
        );
    }

    struct Broken;
    impl Write for Broken {
        fn write(&mut self, _: &[u8]) -> io::Result<usize> {
            Err(io::Error::other("disk full"))
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn keeps_first_io_error() {
        let mut p = CanonicalPrinter::new(Broken);
        p.emit(
            1,
            &Canon::Feed {
                end: Axes::default(),
            },
        );
        assert!(p.io_error().is_some());
        assert!(p.finish().is_err());
    }
}
