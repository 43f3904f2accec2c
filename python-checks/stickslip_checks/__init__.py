"""stickslip_checks: the fmpy harness of the stick-slip beam FMUs.

Modules:
- artifacts: where the FMUs and the `stickslip` binary are; value references and
  choices from each modelDescription.xml
- master: the co-simulation master (Jacobi, Gauss-Seidel) over fmpy's FMU2Slave
- slip_metrics: breakaway, major slips, period, phase shift of a sampled run
- parameters, sweep_engine, stick_slip_map: the Dask sweep and the stick-slip map
- plots: every figure
Entry points (python -m stickslip_checks.<name>, or the console scripts of
pyproject.toml): fmu_scene, cosim_convergence, sweep, training, sklearn_peer, plot_cli,
study_plot.
"""
