// icgm_eval_traj: accuracy of an estimated trajectory against ground truth (TUM format), as
// the TUM RGB-D benchmark's evaluate_ate / evaluate_rpe do, plus an optional PNG figure.
#include <algorithm>
#include <cstdio>
#include <numeric>
#include <exception>
#include <string>

#include "core/common/status.h"
#include "core/dataset/trajectory.h"
#include "core/eval/error_terms.h"
#include "core/eval/trajectory_evaluation.h"
#include "core/eval/trajectory_plot.h"
#include "tools/cli_args.h"

namespace {

constexpr char kUsage[] =
    "usage: icgm_eval_traj --gt GT.txt --est EST.txt [--plot out.png] [--sim3]\n"
    "                      [--max-dt 0.02] [--rpe-delta 1.0] [--title TEXT] [--worst N]\n"
    "                      [--error-terms]\n"
    "  Aligns EST to GT (Horn, SE(3); Sim(3) with --sim3) on poses associated within\n"
    "  --max-dt seconds and prints ATE and RPE (per second over --rpe-delta seconds).\n"
    "  --worst N lists the N poses with the largest ATE (stamp, error).\n"
    "  --error-terms fits the error per axis of the first camera as a time lead times the\n"
    "  velocity plus a scale error times the displacement (core/eval/error_terms.h) and\n"
    "  prints both terms and how much of the ATE each explains.\n";
constexpr icgm::tools::ToolInfo kTool{"icgm_eval_traj", kUsage};

int UsageError(const std::string& message) { return icgm::tools::UsageError(kTool, message); }

void PrintStats(const char* name, const icgm::ErrorStats& s, double unit, const char* unit_name) {
  std::printf("%-16s rmse %9.4f  mean %9.4f  median %9.4f  std %9.4f  max %9.4f  %s  (%zu)\n", name,
              s.rmse * unit, s.mean * unit, s.median * unit, s.std_dev * unit, s.max * unit,
              unit_name, s.count);
}

}  // namespace

int main(int argc, char** argv) {
  icgm::TrajectoryEvalOptions options;
  std::string gt_path, est_path, plot_path, title;
  int worst = 0;
  bool error_terms = false;
  try {
    const icgm::tools::CliArgs args(
        argc, argv, {"gt", "est", "plot", "max-dt", "rpe-delta", "title", "worst"},
        {"sim3", "error-terms"});
    if (args.help()) return icgm::tools::PrintUsage(kTool);
    if (!args.positional().empty()) {
      return UsageError("unexpected argument '" + args.positional().front() + "'");
    }
    gt_path = args.Require("gt");
    est_path = args.Require("est");
    plot_path = args.Get("plot");
    options.estimate_scale = args.Has("sim3");
    options.max_dt_s = args.GetDouble("max-dt", options.max_dt_s);
    options.rpe_delta_s = args.GetDouble("rpe-delta", options.rpe_delta_s);
    title = args.Get("title", est_path);
    worst = args.GetInt("worst", 0);
    error_terms = args.Has("error-terms");
    if (worst < 0) return UsageError("--worst must be >= 0");
    if (!(options.max_dt_s >= 0.0)) return UsageError("--max-dt must be >= 0");
    if (!(options.rpe_delta_s > 0.0)) return UsageError("--rpe-delta must be > 0");
  } catch (const std::invalid_argument& e) {
    return UsageError(e.what());
  }

  try {
    const icgm::Trajectory gt = icgm::ReadTumTrajectory(gt_path);
    const icgm::Trajectory est = icgm::ReadTumTrajectory(est_path);
    icgm::TrajectoryEvaluation ev;
    const icgm::Status s = icgm::EvaluateTrajectory(gt, est, options, &ev);
    if (!s.ok()) {
      std::fprintf(stderr, "icgm_eval_traj: %s\n", s.reason().c_str());
      return 1;
    }
    std::printf(
        "poses            %zu associated of %zu estimated, %zu ground truth (max dt %.3f s)\n",
        ev.num_associated(), ev.num_estimate, ev.num_groundtruth, options.max_dt_s);
    std::printf("alignment        %s", options.estimate_scale ? "Sim(3)" : "SE(3)");
    if (options.estimate_scale) std::printf(", scale %.5f", ev.alignment.scale);
    std::printf("\n");
    PrintStats("ATE", ev.ate, 1.0, "m");
    if (ev.rpe_translation_m_per_s.count > 0) {
      PrintStats("RPE translation", ev.rpe_translation_m_per_s, 1.0, "m/s");
      PrintStats("RPE rotation", ev.rpe_rotation_deg_per_s, 1.0, "deg/s");
    } else {
      std::printf("RPE              n/a (associated poses span less than %.2f s)\n",
                  options.rpe_delta_s);
    }
    if (worst > 0) {
      std::vector<size_t> order(ev.ate_m.size());
      std::iota(order.begin(), order.end(), 0);
      std::sort(order.begin(), order.end(),
                [&](size_t a, size_t b) { return ev.ate_m[a] > ev.ate_m[b]; });
      order.resize(std::min(order.size(), static_cast<size_t>(worst)));
      std::printf("worst poses (stamp, ATE m):\n");
      for (size_t i : order) {
        std::printf("  %s  %.4f\n", ev.stamps[i].ToString().c_str(), ev.ate_m[i]);
      }
    }
    if (error_terms) {
      icgm::ErrorTerms terms;
      const icgm::Status fitted = icgm::FitErrorTerms(gt, ev, &terms);
      if (!fitted.ok()) {
        std::fprintf(stderr, "icgm_eval_traj: error terms: %s\n", fitted.reason().c_str());
        return 1;
      }
      std::printf("error terms      per axis of the first camera (x right, y down, z forward), %zu poses\n",
                  terms.poses);
      std::printf("  time lead      %+8.4f %+8.4f %+8.4f  s (estimate ahead of the truth)\n",
                  terms.lead_s.x(), terms.lead_s.y(), terms.lead_s.z());
      std::printf("  scale error    %+7.2f%% %+7.2f%% %+7.2f%%  of the displacement\n",
                  100.0 * terms.scale_error.x(), 100.0 * terms.scale_error.y(),
                  100.0 * terms.scale_error.z());
      std::printf("  ATE rmse %.4f m; left after the lead term %.4f m, the scale term %.4f m, both %.4f m\n",
                  terms.ate_rmse_m, terms.rmse_after_lead_m, terms.rmse_after_scale_m,
                  terms.rmse_after_both_m);
    }
    if (!plot_path.empty()) {
      icgm::TrajectoryPlotOptions plot_options;
      plot_options.title = title;
      const icgm::Status written = icgm::WriteTrajectoryPlot(plot_path, gt, est, ev, plot_options);
      if (!written.ok()) {
        std::fprintf(stderr, "icgm_eval_traj: %s\n", written.reason().c_str());
        return 1;
      }
      std::printf("plot             %s\n", plot_path.c_str());
    }
  } catch (const icgm::LoadError& e) {
    std::fprintf(stderr, "icgm_eval_traj: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "icgm_eval_traj: unexpected error: %s\n", e.what());
    return 1;
  }
  return 0;
}
