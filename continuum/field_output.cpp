#include "continuum/field_output.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "continuum/h5_writer.hpp"
#include "grainscale_version.hpp"

namespace grainscale::continuum {

void write_continuum_h5(const std::string& path, const Model& model, const SurfaceCoverage& observation,
                        const RunRecord& record) {
  const Grid& g = model.grid();
  const auto nx = static_cast<hsize_t>(g.nx()), nz = static_cast<hsize_t>(g.nz());
  const auto nt = static_cast<hsize_t>(record.times.size());
  H5Writer h5(path);
  h5.attribute("/", "format", std::string("grainscale-continuum"));
  h5.attribute("/", "format_version", kContinuumFormatVersion);
  h5.attribute("/", "grainscale_version", std::string(grainscale::version));
  h5.attribute("/", "git_revision", std::string(grainscale::git_revision));

  h5.group("/grid");
  std::vector<double> xc(nx), xf(nx + 1), hn(nx + 1), sc(nz), zc(nx * nz), area(nx * nz);
  for (int i = 0; i < g.nx(); ++i) xc[i] = g.x_centre(i);
  for (int f = 0; f <= g.nx(); ++f) {
    xf[f] = g.x_face(f);
    hn[f] = g.h_node(f);
  }
  for (int k = 0; k < g.nz(); ++k) sc[k] = g.sigma_centre(k);
  for (int i = 0; i < g.nx(); ++i) {
    for (int k = 0; k < g.nz(); ++k) {
      zc[g.index(i, k)] = g.z_centre(i, k);
      area[g.index(i, k)] = g.area(i, k);
    }
  }
  h5.dataset("/grid/x_centre", {nx}, xc);
  h5.dataset("/grid/x_face", {nx + 1}, xf);
  h5.dataset("/grid/surface_height", {nx + 1}, hn);
  h5.dataset("/grid/sigma_centre", {nz}, sc);
  h5.dataset("/grid/z_centre", {nx, nz}, zc);
  h5.dataset("/grid/area", {nx, nz}, area);

  std::vector<double> c, cov, chaff, surface, depth;
  for (std::size_t n = 0; n < nt; ++n) {
    const Grid& gn = record.grid(model, n);
    c.insert(c.end(), record.fields[n].begin(), record.fields[n].end());
    const auto cv = observation.coverage(gn, record.fields[n]);
    cov.insert(cov.end(), cv.begin(), cv.end());
    chaff.push_back(gn.integrate(record.fields[n]));
    surface.insert(surface.end(), gn.surface_nodes().begin(), gn.surface_nodes().end());
    depth.insert(depth.end(), gn.column_depths().begin(), gn.column_depths().end());
  }
  h5.dataset("/time", {nt}, record.times);
  h5.dataset("/c", {nt, nx, nz}, c);
  h5.dataset("/coverage", {nt, nx}, cov);
  h5.dataset("/chaff", {nt}, chaff);
  h5.attribute("/", "model_type", std::string(model.closure() == Closure::depth_averaged ? "depth_averaged" : "resolved"));
  if (!record.grids.empty()) {
    // Moving surface: the grid of every output time (cell area = dσ dx column_depth).
    h5.dataset("/surface_height", {nt, nx + 1}, surface);
    h5.dataset("/column_depth", {nt, nx}, depth);
  }

  h5.group("/parameters");
  for (const auto& name : model.parameter_names()) h5.attribute("/parameters", name, model.parameter(name));
  for (const auto& p : observation.parameters().all()) h5.attribute("/parameters", "observation." + p.name, p.value);
  h5.close();
}

std::vector<double> chaff_per_slice(const Model& model, const std::vector<double>& c, double w) {
  return chaff_per_slice(model.grid(), c, w);
}

std::vector<double> chaff_per_slice(const Grid& g, const std::vector<double>& c, double w) {
  const int slices = static_cast<int>(std::ceil(g.length() / w - 1e-9));
  std::vector<double> out(slices, 0.0);
  for (int i = 0; i < g.nx(); ++i) {
    double column = 0;  // chaff per unit length of x in column i [m]
    for (int k = 0; k < g.nz(); ++k) column += c[g.index(i, k)] * g.area(i, k) / g.dx();
    const double x0 = g.x_face(i), x1 = g.x_face(i + 1);
    for (int j = std::max(0, static_cast<int>(x0 / w)); j < slices && j * w < x1; ++j) {
      const double overlap = std::min(x1, (j + 1) * w) - std::max(x0, j * w);
      if (overlap > 0) out[j] += column * overlap;
    }
  }
  return out;
}

std::string slices_csv(const Model& model, const RunRecord& record, double w) {
  const int slices = static_cast<int>(std::ceil(model.grid().length() / w - 1e-9));
  std::string s = "# chaff per unit width [m^2] in slices of x; column header = slice start-end [m]\ntime_s";
  char buf[64];
  for (int j = 0; j < slices; ++j) {
    std::snprintf(buf, sizeof buf, ",%.4g-%.4g", j * w, std::min((j + 1) * w, model.grid().length()));
    s += buf;
  }
  s += "\n";
  for (std::size_t n = 0; n < record.times.size(); ++n) {
    std::snprintf(buf, sizeof buf, "%.9g", record.times[n]);
    s += buf;
    for (double v : chaff_per_slice(record.grid(model, n), record.fields[n], w)) {
      std::snprintf(buf, sizeof buf, ",%.9g", v);
      s += buf;
    }
    s += "\n";
  }
  return s;
}

std::string coverage_csv(const Model& model, const SurfaceCoverage& observation, const RunRecord& record) {
  const Grid& g = model.grid();
  std::string s = "# top-view chaff coverage per column, 1 - exp(-kappa * top-layer chaff); header = column centre x [m]\ntime_s";
  char buf[64];
  for (int i = 0; i < g.nx(); ++i) {
    std::snprintf(buf, sizeof buf, ",%.6g", g.x_centre(i));
    s += buf;
  }
  s += "\n";
  for (std::size_t n = 0; n < record.times.size(); ++n) {
    std::snprintf(buf, sizeof buf, "%.9g", record.times[n]);
    s += buf;
    for (double v : observation.coverage(record.grid(model, n), record.fields[n])) {
      std::snprintf(buf, sizeof buf, ",%.9g", v);
      s += buf;
    }
    s += "\n";
  }
  return s;
}

}  // namespace grainscale::continuum
