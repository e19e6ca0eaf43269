"""What users do next: the run table of `simulate` (`runs`), MJCF, generated C, control, identification, design studies and sweeps."""
