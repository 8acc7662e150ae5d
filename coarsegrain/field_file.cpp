#include "coarsegrain/field_file.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "coarsegrain/hdf5_image.hpp"
#include "dem/atomic_file.hpp"
#include "grainscale_version.hpp"

namespace grainscale::cg {

namespace {

std::string frame_name(std::size_t k) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "%06zu", k);
  return buf;
}

std::vector<double> flat(const std::vector<dem::Vec3>& v) {
  std::vector<double> out;
  out.reserve(3 * v.size());
  for (const auto& a : v) out.insert(out.end(), {a.x, a.y, a.z});
  return out;
}

std::vector<double> flat(const std::vector<std::array<double, 9>>& v) {
  std::vector<double> out;
  out.reserve(9 * v.size());
  for (const auto& a : v) out.insert(out.end(), a.begin(), a.end());
  return out;
}

/// Names of the per-cell datasets of a species group, scalar (1) or vector (3) valued.
struct Item {
  const char* name;
  int components;
};
constexpr Item kSpeciesItems[] = {{"density", 1}, {"volume_fraction", 1}, {"number_density", 1}, {"temperature", 1}, {"velocity", 3}};
constexpr Item kFrameItems[] = {{"chaff_volume_concentration", 1}, {"chaff_number_concentration", 1}, {"chaff_mass_concentration", 1},
                                {"shear_rate", 1}, {"velocity_gradient", 9}, {"chaff_velocity", 3}, {"segregation_flux", 3}};

std::vector<double> species_data(const SpeciesFields& f, const std::string& name) {
  if (name == "density") return f.density;
  if (name == "volume_fraction") return f.volume_fraction;
  if (name == "number_density") return f.number_density;
  if (name == "temperature") return f.temperature;
  return flat(f.velocity);
}

std::vector<double> frame_data(const Fields& f, const std::string& name) {
  if (name == "chaff_volume_concentration") return f.chaff_volume_concentration;
  if (name == "chaff_number_concentration") return f.chaff_number_concentration;
  if (name == "chaff_mass_concentration") return f.chaff_mass_concentration;
  if (name == "shear_rate") return f.shear_rate;
  if (name == "velocity_gradient") return flat(f.velocity_gradient);
  if (name == "chaff_velocity") return flat(f.chaff_velocity);
  return flat(f.segregation_flux);
}

std::vector<hsize_t> cell_dims(const Grid& g, int components) {
  std::vector<hsize_t> d{static_cast<hsize_t>(g.cells[2]), static_cast<hsize_t>(g.cells[1]), static_cast<hsize_t>(g.cells[0])};
  if (components > 1) d.push_back(static_cast<hsize_t>(components));
  return d;
}

void check_group_name(const std::string& n) {
  if (n.empty() || n == "." || n.find('/') != std::string::npos) {
    throw std::invalid_argument("species name '" + n + "' cannot be an HDF5 group name (non-empty, not '.', no '/')");
  }
}

}  // namespace

void write_field_file(const std::string& h5_path, const std::vector<FieldFrame>& frames, const FieldFileInfo& info) {
  if (frames.empty()) throw std::invalid_argument("write_field_file: no frames");
  const Grid& g = frames.front().fields.grid;
  for (const auto& n : frames.front().fields.species_names) check_group_name(n);
  Hdf5Image h5;
  h5.attribute("/", "cg_layout_version", std::int32_t{kFieldLayoutVersion});
  h5.attribute("/", "code_version", std::string(grainscale::version) + " " + grainscale::git_revision);
  h5.attribute("/", "units", std::string("SI: m, kg, s"));
  h5.attribute("/", "kernel", std::string(name(info.kernel.type)));
  h5.attribute("/", "kernel_width", info.kernel.width);
  h5.attribute("/", "kernel_cutoff", info.kernel.cutoff());
  h5.attribute("/", "kernel_width_diameters", info.width_diameters);
  h5.attribute("/", "true_diameter", info.true_diameter);
  h5.attribute("/", "scale_factor", info.scale_factor);
  h5.attribute("/", "boundary", std::string(name(info.kernel.boundary)));
  h5.attribute("/", "container_wall", info.container_wall);
  h5.attribute("/", "species_names", frames.front().fields.species_names);
  h5.attribute("/", "chaff_species", info.chaff_species);
  h5.attribute("/", "snapshots", info.snapshots);
  h5.attribute("/", "max_mass_error", info.max_mass_error);

  h5.group("/grid");
  h5.attribute("/grid", "dimension", std::int32_t{g.dimension});
  h5.attribute("/grid", "lo", std::vector<double>{g.lo.x, g.lo.y, g.lo.z});
  h5.attribute("/grid", "hi", std::vector<double>{g.hi.x, g.hi.y, g.hi.z});
  h5.attribute("/grid", "cells", std::vector<std::int32_t>{g.cells[0], g.cells[1], g.cells[2]});
  const char* axis_names[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    std::vector<double> edges, centres;
    for (int i = 0; i <= g.cells[static_cast<std::size_t>(a)]; ++i) edges.push_back(g.edge(a, i));
    for (int i = 0; i < g.cells[static_cast<std::size_t>(a)]; ++i) centres.push_back(g.centre(a, i));
    h5.dataset(std::string("/grid/") + axis_names[a] + "_edges", {edges.size()}, edges);
    h5.dataset(std::string("/grid/") + axis_names[a], {centres.size()}, centres);
  }

  h5.group("/frames");
  h5.attribute("/frames", "count", static_cast<std::int32_t>(frames.size()));
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const Fields& f = frames[k].fields;
    const std::string fr = "/frames/" + frame_name(k);
    h5.group(fr);
    h5.attribute(fr, "time", f.time);
    h5.attribute(fr, "snapshots", static_cast<std::int32_t>(f.snapshots));
    h5.attribute(fr, "averaging", frames[k].averaging);
    const bool phase = frames[k].averaging == "phase";
    const double nan = std::numeric_limits<double>::quiet_NaN();
    h5.attribute(fr, "phase_lo", phase ? frames[k].phase_lo : nan);
    h5.attribute(fr, "phase_hi", phase ? frames[k].phase_hi : nan);
    auto write_species = [&](const std::string& group, const SpeciesFields& sf) {
      h5.group(group);
      for (const Item& it : kSpeciesItems) h5.dataset(group + "/" + it.name, cell_dims(g, it.components), species_data(sf, it.name));
    };
    write_species(fr + "/mixture", f.mixture);
    h5.group(fr + "/species");
    for (std::size_t s = 0; s < f.species.size(); ++s) write_species(fr + "/species/" + f.species_names[s], f.species[s]);
    for (const Item& it : kFrameItems) h5.dataset(fr + "/" + it.name, cell_dims(g, it.components), frame_data(f, it.name));
    if (!f.surface_height.empty()) {
      h5.dataset(fr + "/surface_height", {static_cast<hsize_t>(g.cells[1]), static_cast<hsize_t>(g.cells[0])}, f.surface_height);
    }
  }
  dem::write_file_atomically(h5_path, h5.finish());
}

void write_field_xdmf(const std::string& xmf_path, const std::string& h5_reference, const std::vector<FieldFrame>& frames) {
  std::ostringstream x;
  x.precision(17);
  x << "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf Version=\"2.0\">\n <Domain>\n"
    << "  <Grid Name=\"coarse-grained fields\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const Fields& f = frames[k].fields;
    const Grid& g = f.grid;
    const std::string fr = "/frames/" + frame_name(k);
    const std::string cells = std::to_string(g.cells[2]) + " " + std::to_string(g.cells[1]) + " " + std::to_string(g.cells[0]);
    x << "   <Grid Name=\"frame " << k << "\" GridType=\"Uniform\">\n"
      << "    <Time Value=\"" << f.time << "\"/>\n"
      << "    <Topology TopologyType=\"3DCoRectMesh\" Dimensions=\"" << g.cells[2] + 1 << " " << g.cells[1] + 1 << " "
      << g.cells[0] + 1 << "\"/>\n"
      << "    <Geometry GeometryType=\"ORIGIN_DXDYDZ\">\n"  // values in z, y, x order, like the dimensions
      << "     <DataItem Format=\"XML\" Dimensions=\"3\">" << g.lo.z << " " << g.lo.y << " " << g.lo.x << "</DataItem>\n"
      << "     <DataItem Format=\"XML\" Dimensions=\"3\">" << g.spacing(2) << " " << g.spacing(1) << " " << g.spacing(0)
      << "</DataItem>\n    </Geometry>\n";
    auto attribute = [&](const std::string& label, const std::string& path, int components) {
      const char* type = components == 1 ? "Scalar" : components == 3 ? "Vector" : "Tensor";
      x << "    <Attribute Name=\"" << label << "\" AttributeType=\"" << type << "\" Center=\"Cell\">\n"
        << "     <DataItem Format=\"HDF\" NumberType=\"Float\" Precision=\"8\" Dimensions=\"" << cells;
      if (components > 1) x << ' ' << components;
      x << "\">" << h5_reference << ":" << path << "</DataItem>\n    </Attribute>\n";
    };
    for (const Item& it : kSpeciesItems) attribute(it.name, fr + "/mixture/" + it.name, it.components);
    for (std::size_t s = 0; s < f.species.size(); ++s)
      for (const Item& it : kSpeciesItems)
        attribute(f.species_names[s] + "_" + it.name, fr + "/species/" + f.species_names[s] + "/" + it.name, it.components);
    for (const Item& it : kFrameItems) attribute(it.name, fr + "/" + it.name, it.components);
    x << "   </Grid>\n";
  }
  x << "  </Grid>\n </Domain>\n</Xdmf>\n";
  dem::write_file_atomically(xmf_path, x.str());
}

}  // namespace grainscale::cg
