//! Parameter storage: numbered parameters `#1`–`#5601`, named parameters (`#<name>` local to the
//! subroutine level that assigns it, `#<_name>` global). Under Fanuc's rules a numbered
//! parameter may hold a vacant variable's value ([`vacant`](super::expr::vacant)). The assignments of a line are collected
//! in its [`Block`](super::block::Block) and applied only after the whole line has been read, as
//! in LinuxCNC.

use std::collections::HashMap;

use super::expr::{vacant, MAX_PARAM};

/// The Fanuc variables that are vacant until assigned: the local (#1–#33) and common
/// (#100–#199, #500–#999) variables. (`#0` is always vacant; the others are system
/// variables, or LinuxCNC's parameters, which read 0 as in LinuxCNC.)
const FANUC_VACANT: [std::ops::RangeInclusive<usize>; 3] = [1..=33, 100..=199, 500..=999];

/// Numbered parameters that are arguments of an O-word subroutine call and local to it.
pub(crate) const N_ARGS: usize = 30;

/// What a pass of the main program changed (see `Interp::restart_main`): every numbered
/// parameter it stored (those that are views of the control's state, such as offsets, are
/// compared through `PassControl` instead) and every global or main-level named parameter it
/// wrote, with the value it had when the pass began. The log costs a little per distinct
/// parameter written, not per parameter.
#[derive(Debug, Default)]
pub(crate) struct PassLog {
    /// Numbered parameters written, with their bits when the pass began.
    nums: Vec<(usize, u64)>,
    /// Which numbered parameters are in `nums`, a bit each.
    seen: Vec<u64>,
    /// Named parameters written, with their bits when the pass began (`None`: unset then).
    names: HashMap<String, Option<u64>>,
}

impl PassLog {
    fn new() -> Self {
        PassLog {
            nums: Vec::new(),
            seen: vec![0; (MAX_PARAM + 1).div_ceil(64)],
            names: HashMap::new(),
        }
    }

    /// Whether any parameter written since the log was cleared now differs from its value then.
    pub(crate) fn changed(&self, p: &Params) -> bool {
        self.nums.iter().any(|&(n, old)| p.num[n].to_bits() != old)
            || self
                .names
                .iter()
                .any(|(k, old)| p.named_at_main(k).map(f64::to_bits) != *old)
    }

    /// Starts a new pass.
    pub(crate) fn clear(&mut self) {
        self.names.clear();
        for (n, _) in self.nums.drain(..) {
            self.seen[n / 64] &= !(1 << (n % 64));
        }
    }
}

/// At most this many assignments on one line (LinuxCNC's `MAX_NAMED_PARAMETERS` per line is 50).
pub(crate) const MAX_ASSIGNS: usize = 50;

/// Where an assignment goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Target {
    /// A numbered parameter.
    Num(usize),
    /// A named parameter: its name as a range of the line's normalised code.
    Named(u32, u32),
}

/// The parameter tables.
#[derive(Debug)]
pub(crate) struct Params {
    /// Numbered parameters, index = number (index 0 unused).
    pub(crate) num: Vec<f64>,
    /// Global named parameters (names starting with `_`).
    pub(crate) globals: HashMap<String, f64>,
    /// Local named parameters, one table per call level (index 0: the main program).
    pub(crate) locals: Vec<HashMap<String, f64>>,
    /// What the current pass of the main program wrote.
    pub(crate) pass: PassLog,
}

impl Default for Params {
    fn default() -> Self {
        Self {
            num: vec![0.0; MAX_PARAM + 1],
            globals: HashMap::new(),
            locals: vec![HashMap::new()],
            pass: PassLog::new(),
        }
    }
}

impl Params {
    /// The tables a program starts with: all 0 but LinuxCNC's #5599 (DEBUG messages shown),
    /// which starts at 1.
    pub(crate) fn linuxcnc_or_fanuc(fanuc: bool) -> Self {
        let mut p = Self::default();
        if !fanuc {
            p.num[5599] = 1.0;
        }
        p
    }

    /// A named parameter as stored (globals for `_` names, else the current level's locals).
    pub(crate) fn get_named(&self, name: &str) -> Option<f64> {
        if name.starts_with('_') {
            self.globals.get(name).copied()
        } else {
            self.locals.last().and_then(|m| m.get(name).copied())
        }
    }

    /// A global, or a named parameter of the main program's level.
    fn named_at_main(&self, name: &str) -> Option<f64> {
        if name.starts_with('_') {
            self.globals.get(name).copied()
        } else {
            self.locals.first().and_then(|m| m.get(name).copied())
        }
    }

    /// Fanuc: makes the local and common variables vacant ([`vacant`]), as they are when a
    /// program starts.
    pub(crate) fn start_vacant(&mut self) {
        for r in FANUC_VACANT {
            self.num[r].fill(vacant());
        }
    }

    /// Sets numbered parameter `n` (a plain store: the control's own are the caller's).
    pub(crate) fn set_num(&mut self, n: usize, v: f64) {
        if self.pass.seen[n / 64] & (1 << (n % 64)) == 0 {
            self.pass.seen[n / 64] |= 1 << (n % 64);
            self.pass.nums.push((n, self.num[n].to_bits()));
        }
        self.num[n] = v;
    }

    /// Sets a named parameter; allocates only the first time a name is assigned at a level.
    pub(crate) fn set_named(&mut self, name: &str, v: f64) {
        if (name.starts_with('_') || self.locals.len() == 1) && !self.pass.names.contains_key(name)
        {
            let old = self.named_at_main(name).map(f64::to_bits);
            self.pass.names.insert(name.to_string(), old);
        }
        let map = if name.starts_with('_') {
            &mut self.globals
        } else {
            self.locals
                .last_mut()
                .expect("the main level always exists")
        };
        if let Some(slot) = map.get_mut(name) {
            *slot = v;
        } else {
            map.insert(name.to_string(), v);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scopes() {
        let mut p = Params::default();
        p.set_named("a", 1.0);
        p.set_named("_g", 2.0);
        p.locals.push(HashMap::new());
        assert_eq!(p.get_named("a"), None);
        assert_eq!(p.get_named("_g"), Some(2.0));
        p.set_named("a", 3.0);
        assert_eq!(p.get_named("a"), Some(3.0));
        p.locals.pop();
        assert_eq!(p.get_named("a"), Some(1.0));
    }
}
