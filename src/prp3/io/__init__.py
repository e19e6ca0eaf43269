"""File formats (`tables`: CSV and Parquet; `trajectory`: TRAJ.csv; `measurements`; `forces`) and the registry of output quantities (`results`)."""
