"""Simulators users run from the CLI: a load cell on a 24-bit converter
(L6D + ADS1232-like: noise, glitches, creep, swing) and a thermal chamber
with a drifting magnetometer (QMC5883L-like).

===================  =====================================================
LoadCellParams       every parameter of the load-cell run
simulate_loadcell    a run: time, true load, counts (a dict of arrays)
write_loadcell_run   the run as CSV or Parquet
ChamberParams        every parameter of the chamber run
simulate_chamber     a run: time, chamber and sensor temperature, readings
write_chamber_run    the run as CSV or Parquet
===================  =====================================================
"""
from ._chamber import ChamberParams
from ._chamber import simulate as simulate_chamber
from ._chamber import write as write_chamber_run
from ._loadcell import LoadCellParams
from ._loadcell import simulate as simulate_loadcell
from ._loadcell import write_run as write_loadcell_run

__all__ = ["LoadCellParams", "simulate_loadcell", "write_loadcell_run", "ChamberParams", "simulate_chamber",
           "write_chamber_run"]
