"""Nav2's docking (opennav_docking) below its server: the dock plugins (`charging_dock`),
the dock database, the graceful approach controller and the detection filter."""
