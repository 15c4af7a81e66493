//! RS274/NGC (LinuxCNC) and common Fanuc G-code interpreter.
