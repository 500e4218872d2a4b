# The sanitizer pass (tools/test.sh --sanitize): the tests that took 10 s or more (seconds, rounded).
# A name that this build does not define (a pass-only test) is ignored.
# Pairs of test name and seconds; apply.cmake sets them (read after this file).
set(canopy_test_costs
  cli.reliability3                                                        81
  Mission.OverlappedMovesGiveTheSameViewsAsMovesInLine                    77
  experiment_cli                                                          64
  cli.hardening                                                           57
  cli.bad_input                                                           51
  mission_cli                                                             42
  Mission.TheIndexAndEnvironmentNearTheRobotGiveTheSameMission            39
  cli.reliability                                                         38
  SemanticOcTree.AMapWithItsFarPartMovedOutIsTheWholeMap                  14
  IncrementalEvaluator.EqualsTheFullEvaluationAfterEveryRandomBatch       33
  cli.import_plant                                                        29
  Mission.PredefinedReplacesFailedScriptedViews                           29
  cli.textured_plant                                                      28
  RenderCulling.DepthOnlyRenderIsTheFullRendersDepthBitForBit             28
  Renderer.AWindowBuiltAgainRendersAsAFreshOneAndAsTheWholeRowInRange     26
  DatasetExport.BackProjectedDepthLandsOnTheTrueSurface                   26
  Visibility.DensePresetMatchesTheCommercialCrop                          22
  MissionMcap.TheExportOfTheRunFolderIsTheRecordingMadeWhileItRan         22
  MissionLoop.EveryStopMeetsItsBudgetOrSaysWhyNot                         20
  nbv_ablate_smoke                                                        20
  McapFramesFoxglove.ZedRecordingMapsAsItsFrames                          19
  SimulatorWindow.APreparedWindowIsTheModelBuiltOnArrivalBitForBit        19
  Oracle.OraclePlannersRunInAMissionAndSayTheyReadTheTruth                19
  Oracle.OracleOnLearnedsCandidatesScoresThemByTheTruth                   11
  McapFramesFoxglove.RealSenseRecordingMapsAsItsFrames                    18
  cli.frames                                                              18
  Mission.SameSeedSameViews                                               18
  RenderCulling.ShadowsOfGeomsOutsideTheViewAreKept                       18
  RenderVideoFrame.CoarseCylindersDrawFewerTrianglesAndChangeOnlyTheRobot 17
  McapFramesFoxglove.RealSensePngRecordingMapsAsItsFrames                 17
  Mission.PredefinedRefusesViewsThatWouldFailBeforeTheMove                17
  RenderCulling.ShadowedChaseViewsAreIdenticalWithAndWithoutCulling       16
  MissionMcap.RefusesWhatItCannotRecord                                   15
  RenderVideoFrame.LooksAsTheFullRenderWhileTheArmMovesUnderAStillCamera  15
  MissionMcap.RecordingChangesNothingTheMissionDoes                       15
  mission_video                                                           15
  McapReader.RefusesEveryCut                                              15
  MissionLoop.TheExplorationPlannerFillsTheBudgetOfAMethodWithNothingLeft 15
  RenderCulling.WristFramesAreIdenticalWithAndWithoutCulling              14
  MissionLoop.AViewThatFailedIsNeverAttemptedAgainAtTheStop               14
  RenderVideoFrame.TheArmAmongThePlantsIsHiddenWhereTheFullRenderHidesIt  13
  MissionJob.RunFolderHoldsWhatTheMissionGivesOnItsOwn                    12
  McapFrames.ChoosesRealSenseTopicsAndMapsSixteenBitDepth                 12
  MissionFaults.AFarStopGetsTheDrivesLeastTimeOnTopOfTheTimeout           11
  ArmPlannerTest.StraightPlanIsThePlanWhenItIsTheStraightLine             11
  MissionFaults.PlannerTimeoutIsCountedAndTheMissionGoesOn                11
  RenderVideoFrame.ARepeatedStateGivesTheLastFrameWithoutDrawing          11
  McapFrames.AMissionsRecordingMapsBackToItsMapByteForByte                11
  McapJobFoxglove.FoxglovesReaderDecodesAMissionsRecording                10
  McapFrames.RefusesInOneLineAndWritesNothing                             10
)
