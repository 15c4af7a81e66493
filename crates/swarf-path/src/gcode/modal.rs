//! LinuxCNC's modal state save and restore: `M70` saves the modal state of the current call
//! level, `M71` forgets it, `M72` restores it, and `M73` saves it to be restored when the
//! subroutine returns (`endsub`, `return`, or `M99` of an `M98` subprogram). What is saved is
//! LinuxCNC's list as far as the reader models it: units, plane, distance and arc distance
//! modes, feed mode and feed, spindle speed and direction, the coordinate system, the retract
//! mode, the tool length offset, the cutter radius compensation (restoring a different one is
//! refused: the compensated path would need its entry move), coolant, overrides and the
//! spindle's speed mode (which only the predefined named parameters read). Path control changes
//! no motion and is not kept.

use super::interp::{Interp, ReadOnlyState};
use super::{Fault, Res, Span};
use crate::{Canon, FeedMode, PathErrorKind, Plane, SpindleDir, Units};

/// The modal state `M70`/`M73` keep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ModalState {
    units: Units,
    plane: Plane,
    absolute: bool,
    arc_absolute: bool,
    feed_mode: FeedMode,
    feed: f64,
    rpm: f64,
    dir: SpindleDir,
    coord: usize,
    retract_r: bool,
    tlo: [f64; 6],
    /// Compensation code, coolant, overrides, spindle mode, offset flag (the tools in it are
    /// not restored).
    read_only: ReadOnlyState,
}

/// A saved state and whether it is restored automatically on return (`M73`).
pub(crate) type Saved = Option<(ModalState, bool)>;

impl Interp<'_, '_> {
    pub(crate) fn modal_state(&self) -> ModalState {
        ModalState {
            units: self.units,
            plane: self.plane,
            absolute: self.absolute,
            arc_absolute: self.arc_absolute,
            feed_mode: self.feed_mode,
            feed: self.feed,
            rpm: self.rpm,
            dir: self.dir,
            coord: self.coord,
            retract_r: self.retract_r,
            tlo: self.tlo,
            read_only: self.read_only,
        }
    }

    /// The saved state of the current call level.
    fn saved_slot(&mut self) -> &mut Saved {
        let level = self.frames.len();
        if self.saved_modal.len() <= level {
            self.saved_modal.resize(level + 1, None);
        }
        &mut self.saved_modal[level]
    }

    /// `M70`–`M73` (`m`), at code span `span`.
    pub(crate) fn modal_save_restore(&mut self, m: u16, span: Span) -> Res<()> {
        match m {
            // M70 keeps a restore on return an M73 at this level asked for (LinuxCNC sets the
            // context valid without clearing that flag).
            70 | 73 => {
                let state = self.modal_state();
                let slot = self.saved_slot();
                let auto = m == 73 || slot.is_some_and(|s| s.1);
                *slot = Some((state, auto));
            }
            71 => *self.saved_slot() = None,
            _ => {
                let Some((s, _)) = *self.saved_slot() else {
                    return Err(Fault::semantic(
                        span,
                        "M72 without a modal state saved at this call level (M70 or M73)",
                    ));
                };
                self.restore_modal(s, span)?;
            }
        }
        Ok(())
    }

    /// On a subroutine's return (its frame not yet popped): restores the state its `M73`
    /// saved, and forgets the level's saved state.
    pub(crate) fn modal_on_return(&mut self, span: Span) -> Res<()> {
        let level = self.frames.len();
        let saved = self.saved_modal.get(level).copied().flatten();
        self.saved_modal.truncate(level);
        match saved {
            Some((s, true)) => self.restore_modal(s, span),
            _ => Ok(()),
        }
    }

    fn restore_modal(&mut self, s: ModalState, span: Span) -> Res<()> {
        if s.read_only.ccomp != self.read_only.ccomp {
            return Err(Fault::new(
                PathErrorKind::Unsupported,
                span,
                "restoring a modal state with another cutter radius compensation state is not \
                 supported",
                "G40 or the same compensation when the state is saved and restored",
            ));
        }
        if s.units != self.units {
            self.units = s.units;
            self.scale = s.units.mm_per_unit();
            self.emit(Canon::Units(s.units));
        }
        if s.plane != self.plane {
            self.plane = s.plane;
            self.emit(Canon::Plane(s.plane));
        }
        self.absolute = s.absolute;
        self.arc_absolute = s.arc_absolute;
        self.retract_r = s.retract_r;
        if s.feed_mode != self.feed_mode {
            self.feed_mode = s.feed_mode;
            self.emit(Canon::FeedMode(s.feed_mode));
        }
        if s.feed != self.feed {
            self.feed = s.feed;
            self.emit(Canon::FeedRate(s.feed));
        }
        if (s.rpm, s.dir) != (self.rpm, self.dir) {
            (self.rpm, self.dir) = (s.rpm, s.dir);
            self.emit(Canon::Spindle {
                rpm: s.rpm,
                dir: s.dir,
            });
        }
        if s.tlo != self.tlo {
            self.set_tlo(s.tlo);
            self.emit(Canon::ToolLengthOffset(s.tlo[2]));
        }
        self.read_only = ReadOnlyState {
            loaded_tool: self.read_only.loaded_tool,
            selected_tool: self.read_only.selected_tool,
            ..s.read_only
        };
        if s.coord != self.coord {
            self.coord = s.coord;
            let off = self.g5x_table[s.coord - 1];
            self.set_frame(off, self.g92, self.rot_table[s.coord - 1]);
        }
        Ok(())
    }
}
