"""The robot: its parameters (`robot`), its effects as elements (`elements`) and the motion (`motion`)."""
