#include "poseset_summary.h"


#include <iomanip>

namespace cdbench::cli {

void print_level_table(std::ostream& out, const nlohmann::json& ps, double diag) {
  out << std::left << std::setw(14) << "level" << std::setw(14) << "target" << std::setw(9) << "poses" << std::setw(11)
      << "certified" << std::setw(11) << "on-target" << std::setw(11) << "no-contact" << std::setw(15) << "raw-err/diag"
      << "steps\n";
  for (const auto& l : ps["levels"]) {
    out << std::left << std::setw(14) << l["spec"].get<std::string>() << std::setw(14) << std::setprecision(6)
        << l["target"].get<double>() << std::setw(9) << l["poses"].get<std::size_t>() << std::setw(11)
        << l["certified"].get<std::size_t>() << std::setw(11) << l["on_target"].get<std::size_t>() << std::setw(11)
        << l["no_contact"].get<std::size_t>() << std::setw(15) << std::setprecision(3)
        << l["raw_placement_error"]["mean"].get<double>() / diag << std::setprecision(3)
        << l["mean_polish_steps"].get<double>() << "\n";
  }
}

}  // namespace cdbench::cli
