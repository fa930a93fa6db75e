#pragma once
// `vpm study`: the estimator study (issue 4). Returns the process exit code.
namespace vpm {
int run_study(int argc, char** argv);
}
