//! APT CL data (CLDATA text) reader.
