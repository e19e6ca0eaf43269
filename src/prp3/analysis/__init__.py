"""The problems solved with the mechanics: inverse dynamics by one of three methods, forward dynamics, the workspace."""
