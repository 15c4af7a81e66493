//! Machine kinematics: joint values to tool tip and axis in the workpiece frame.
