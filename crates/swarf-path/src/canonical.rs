//! Prints canonical events in the exact form of LinuxCNC interpreter tests.
