"""Linkage analysis and synthesis: four-bar kinematics, conventions, planting metrics, dynamics."""
