# The Release pass (tools/test.sh): the tests that took 8 s or more (seconds, rounded).
# A name that this build does not define (a pass-only test) is ignored.
# Pairs of test name and seconds; apply.cmake sets them (read after this file).
set(canopy_test_costs
  cli.headers                                                  259
  mission_golden_views                                         70
  cli.interrupt                                                48
  mission_golden_oracle                                        39
  python.bags                                                  38
  jobs_report_browser                                          32
  cli.install                                                  30
  cli.reliability3                                             23
  python.interrupts                                            22
  python.missions                                              20
  experiment_cli                                               20
  cli.hardening                                                18
  cli.bad_input                                                16
  experiment_slurm                                             16
  McapReader.RefusesEveryCut                                   14
  mission_cli                                                  12
  Mission.OverlappedMovesGiveTheSameViewsAsMovesInLine         12
  cli.reliability                                              10
  cli.import_plant                                             10
  cli.textured_plant                                           9
  python.reliability                                           9
  Mission.TheIndexAndEnvironmentNearTheRobotGiveTheSameMission 9
)
