//! The APT generic cutter, its surface pieces, holders and tool tables.
