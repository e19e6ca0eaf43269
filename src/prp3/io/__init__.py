"""File formats (`formats`: CSV, Parquet, TRAJ.csv, forces, measurements) and the registry of output quantities (`results`)."""
