//! Which cutter each tool number of a program is: one resolution policy for every operation.
//!
//! A program names tools by number (`T3 M6`, APT `LOADTL/3`) and may define their geometry itself
//! (APT `CUTTER/`). A [`ToolSet`] maps numbers to [`Cutter`]s by one policy, in this order:
//! a single cutter given for every tool (`--tool SPEC`), else the tool library's entry
//! (`--tools FILE`), else the program's own `CUTTER/` record. Numbers nothing defines are
//! reported, not guessed.
//!
//! ```
//! use swarf_tool::{Cutter, ToolSet};
//! let set = ToolSet::single(Cutter::flat(6.0).unwrap());
//! assert_eq!(set.get(7).unwrap().max_diameter(), 6.0);
//! let defs = [(2, [10.0, 0.0, 5.0, 0.0, 0.0, 0.0, 30.0])];
//! let (set, undefined) = ToolSet::resolve(&[1, 2], &defs, None, None).unwrap();
//! assert_eq!(undefined, vec![1]);
//! assert_eq!(set.get(2).unwrap().max_diameter(), 10.0);
//! ```

use std::collections::BTreeMap;

use crate::error::ToolError;
use crate::table::ToolTable;
use crate::Cutter;

/// Where a tool's cutter came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ToolSource {
    /// One cutter given for every tool.
    Spec,
    /// The tool library.
    Table,
    /// The program's own `CUTTER/` definition.
    Program,
}

/// One tool number's cutter and where it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct ResolvedTool {
    /// The cutter.
    pub cutter: Cutter,
    /// Its source.
    pub source: ToolSource,
    /// The library's description of it (empty when it has none).
    pub description: String,
}

/// The cutters of a program by tool number, with an optional cutter for every other number.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ToolSet {
    by_number: BTreeMap<u32, ResolvedTool>,
    default: Option<Cutter>,
}

impl ToolSet {
    /// One cutter for every tool number.
    pub fn single(cutter: Cutter) -> Self {
        Self {
            by_number: BTreeMap::new(),
            default: Some(cutter),
        }
    }

    /// Adds (or replaces) the cutter of tool `n`.
    pub fn with(mut self, n: u32, cutter: Cutter, source: ToolSource) -> Self {
        self.by_number.insert(
            n,
            ResolvedTool {
                cutter,
                source,
                description: String::new(),
            },
        );
        self
    }

    /// The cutter of tool `n`.
    pub fn get(&self, n: u32) -> Option<&Cutter> {
        self.by_number
            .get(&n)
            .map(|r| &r.cutter)
            .or(self.default.as_ref())
    }

    /// The cutter for every number not resolved by number, if any.
    pub fn fallback(&self) -> Option<&Cutter> {
        self.default.as_ref()
    }

    /// The tools resolved by number (without the cutter for every other number).
    pub fn resolved(&self) -> &BTreeMap<u32, ResolvedTool> {
        &self.by_number
    }

    /// Resolves the tool numbers `used` (in order of first use; tool 0 for moves before any
    /// tool is loaded) by the policy of the module documentation: `single` for all, else the
    /// `table`'s entry, else the last `CUTTER/` record of the program for that number
    /// (`program_defs`: number and the seven APT numbers). Returns the set, every used number
    /// recorded with its source, and the numbers nothing defines.
    ///
    /// # Errors
    /// A program `CUTTER/` record that is not a valid cutter.
    pub fn resolve(
        used: &[u32],
        program_defs: &[(u32, [f64; 7])],
        single: Option<&Cutter>,
        table: Option<&ToolTable>,
    ) -> Result<(ToolSet, Vec<u32>), ResolveError> {
        let mut set = ToolSet::default();
        let mut undefined = Vec::new();
        for &n in used {
            let from_program = program_defs.iter().rev().find(|(t, _)| *t == n);
            let resolved = if let Some(c) = single {
                Some(ResolvedTool {
                    cutter: c.clone(),
                    source: ToolSource::Spec,
                    description: String::new(),
                })
            } else if let Some(e) = table.and_then(|t| t.tools.get(&n)) {
                Some(ResolvedTool {
                    cutter: e.cutter.clone(),
                    source: ToolSource::Table,
                    description: e.description.clone(),
                })
            } else if let Some((_, p)) = from_program {
                let cutter = Cutter::from_program_record(*p)
                    .map_err(|source| ResolveError { tool: n, source })?;
                Some(ResolvedTool {
                    cutter,
                    source: ToolSource::Program,
                    description: String::new(),
                })
            } else {
                None
            };
            match resolved {
                Some(r) => {
                    set.by_number.insert(n, r);
                }
                None => undefined.push(n),
            }
        }
        Ok((set, undefined))
    }
}

/// A program's `CUTTER/` record that is not a valid cutter.
#[derive(Debug, thiserror::Error)]
#[error("CUTTER/ definition of tool {tool} in the program")]
pub struct ResolveError {
    /// The tool number.
    pub tool: u32,
    /// What is wrong with it.
    #[source]
    pub source: ToolError,
}
