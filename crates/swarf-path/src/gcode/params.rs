//! Parameter storage: numbered parameters `#1`–`#5601`, named parameters (`#<name>` local to the
//! subroutine level that assigns it, `#<_name>` global). The assignments of a line are collected
//! in its [`Block`](super::block::Block) and applied only after the whole line has been read, as
//! in LinuxCNC.

use std::collections::HashMap;

use super::expr::MAX_PARAM;

/// Numbered parameters that are arguments of an O-word subroutine call and local to it.
pub(crate) const N_ARGS: usize = 30;

/// Numbered parameters below this are the program's own (LinuxCNC's #1–#4999 user parameters,
/// Fanuc's locals and common variables); from #5000 on, the control's state.
pub(crate) const USER_PARAMS: usize = 5000;

/// The parameters a pass of the main program leaves, as bits (see `Interp::restart_main`):
/// two passes that start from equal states run alike.
#[derive(Debug, PartialEq, Eq)]
pub(crate) struct PassState {
    pub(crate) num: Vec<u64>,
    pub(crate) globals: Vec<(String, u64)>,
    pub(crate) locals: Vec<(String, u64)>,
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
}

impl Default for Params {
    fn default() -> Self {
        Self {
            num: vec![0.0; MAX_PARAM + 1],
            globals: HashMap::new(),
            locals: vec![HashMap::new()],
        }
    }
}

impl Params {
    /// A named parameter as stored (globals for `_` names, else the current level's locals).
    pub(crate) fn get_named(&self, name: &str) -> Option<f64> {
        if name.starts_with('_') {
            self.globals.get(name).copied()
        } else {
            self.locals.last().and_then(|m| m.get(name).copied())
        }
    }

    /// Sets a named parameter; allocates only the first time a name is assigned at a level.
    pub(crate) fn set_named(&mut self, name: &str, v: f64) {
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
