"""stickslip_checks: the fmpy harness of the stick-slip beam FMUs.

Library modules:
- artifacts: where the FMUs and the `stickslip` binary are; value references and
  choices from each modelDescription.xml
- master: the co-simulation master (Jacobi, Gauss-Seidel) over fmpy's FMU2Slave;
  other_masters: libcosim, Ecos, fmucontainer and fmpy.ssp on the same systems
- scene, convergence, events, versions: the paper scene through the FMUs, the
  coupling error against h, FMI 3.0 events, FMI 2.0 against 3.0
- retraining, sklearn_peer: the network's retraining and its scikit-learn peer
- parameters, sweep_engine, stick_slip_map, sweep_study: the Dask sweep and the
  stick-slip map
- slip_metrics: breakaway, major slips, period, phase shift of a sampled run
- cli_plots, study, plots: the figures
- tables: the one table writer (text, CSV, DataFrame); runner: what entry points share
- rounding, cpu_kernels: rounding bounds for numbers computed by CPU-dependent kernels,
  and those kernels' fingerprints (scripts/second-cpu.sh)
Entry points (python -m stickslip_checks.<name>, or the console scripts of
pyproject.toml; each only parses its arguments, calls the library and prints):
fmu_scene, cosim_convergence, cosim_events, fmi_versions, masters, sweep, training,
sklearn_peer, plot_cli, study_plot.
"""
