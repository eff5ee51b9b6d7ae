// `qsp show IN -o OUT.png|OUT.svg`: a picture of the partition on its mesh (qsp/render.h).
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>

#include "commands.h"
#include "partitioned.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/render.h"
#include "shared.h"

namespace qsp::cli {
namespace {

struct ShowOptions {
  std::string input, output;
  std::string size = "1024x1024";
  std::string view = "0,0";
  std::string partition;  // "" = the input's default (see load_partitioned)
  std::string format;     // --format for standard input
  bool grid = false;
  bool force = false;
  bool sync = false;
};

bool ends_with(const std::string& s, const char* tail) {
  const std::string t(tail);
  if (s.size() < t.size()) return false;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(s[s.size() - t.size() + i])) != t[i]) return false;
  return true;
}

// One side of --size: decimal digits only, 1 to kMaxRenderSide (from_chars reports overflow where
// sscanf's %u wraps 4294967297 round to 1 and reads "-1" and " 1").
bool parse_side(std::string_view text, std::uint32_t& side) {
  if (text.empty() || text.front() < '0' || text.front() > '9') return false;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), side);
  return ec == std::errc() && end == text.data() + text.size() && side >= 1 && side <= kMaxRenderSide;
}

RenderOptions parse_render_options(const ShowOptions& o) {
  RenderOptions r;
  const std::size_t x = o.size.find('x');
  if (x == std::string::npos || !parse_side(std::string_view(o.size).substr(0, x), r.width) ||
      !parse_side(std::string_view(o.size).substr(x + 1), r.height))
    throw CLI::ValidationError("--size must be WxH with 1 to " + std::to_string(kMaxRenderSide) +
                               " pixels a side, not '" + o.size + "'");
  double az = 0, el = 0;
  char tail = 0;
  if (std::sscanf(o.view.c_str(), "%lf,%lf%c", &az, &el, &tail) != 2 || !std::isfinite(az) ||
      !std::isfinite(el))
    throw CLI::ValidationError("--view must be AZIMUTH,ELEVATION in degrees, not '" + o.view + "'");
  r.azimuth = az, r.elevation = el;
  r.grid = o.grid;
  return r;
}

void run(const ShowOptions& o) {
  const bool svg = ends_with(o.output, ".svg");
  if (!svg && !ends_with(o.output, ".png"))
    throw CLI::ValidationError("-o must name a .png or .svg file, not '" + o.output + "'");
  const RenderOptions ro = parse_render_options(o);
  check_outputs({o.input}, {{o.output, "-o"}});
  const WriteOptions wo{o.force, false, "name another output (-o NAME)", o.sync};
  refuse_existing({{o.output, "-o"}}, wo);  // before the work, not after
  const PartitionedMesh pm = load_partitioned(o.input, o.partition, parse_format_option(o.format));
  const std::string bytes =
      svg ? render_svg(pm.drawn, pm.view, ro) : encode_png(render_image(pm.drawn, pm.view, ro));
  write_output(o.output, bytes, wo);
}

}  // namespace

void register_show(CLI::App& app, int& rc) {
  auto opt = std::make_shared<ShowOptions>();
  CLI::App* sub = app.add_subcommand("show", "Draw the partition on its mesh as a PNG or SVG picture");
  sub->add_option("IN", opt->input, "Mesh (.obj .off .ply) or .qsp file; - for standard input")->required();
  sub->add_option("-o,--output", opt->output, "Picture to write: .png, or .svg (up to 100000 faces)")
      ->required();
  sub->add_option("--size", opt->size, "Picture size WxH in pixels (default 1024x1024)");
  sub->add_option("--view", opt->view,
                  "AZIMUTH,ELEVATION in degrees (default 0,0: looking along -z, +y up, fitted to the mesh)");
  sub->add_option("--partition", opt->partition, kPartitionHelp)
      ->check(CLI::IsMember({"motorcycle", "greedy", "merge", "auto", "stored"}));
  add_format_option(sub, opt->format);
  sub->add_flag("--grid", opt->grid, "Also draw the mesh edges");
  sub->add_flag("-f,--force", opt->force, "Replace the output if it exists (never the input)");
  add_sync_flag(sub, opt->sync);
  sub->callback([opt, &rc] {
    run(*opt);
    rc = 0;
  });
}

}  // namespace qsp::cli
