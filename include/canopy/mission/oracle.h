#pragma once
// The oracle's room, mission/oracle/ (everything in it READS THE GROUND TRUTH): the oracle
// planners (oracle_planners.h), the candidate audit (candidate_audit.h) and candidates.csv with
// the gain-versus-truth table (candidates_csv.h). The truth scorer itself is
// evaluation/truth_score.h. This header includes the three.

#include "canopy/mission/oracle/candidate_audit.h"
#include "canopy/mission/oracle/candidates_csv.h"
#include "canopy/mission/oracle/oracle_planners.h"
