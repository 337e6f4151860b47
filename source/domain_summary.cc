#include <deal.II/base/tensor.h>

#include <signorini/domain_summary.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numeric>
#include <sstream>

namespace Signorini
{
  namespace
  {
    /// The measure of the simplex with the @p n = dim + 1 (cell) or dim
    /// (face) corners @p p.
    template <int dim>
    double
    simplex_measure(const std::vector<Point<dim>> &p)
    {
      const Tensor<1, dim> a = p[1] - p[0];
      if (p.size() == 2)
        return a.norm();
      const Tensor<1, dim> b = p[2] - p[0];
      if (p.size() == 3)
        {
          if constexpr (dim == 2)
            return std::abs(a[0] * b[1] - a[1] * b[0]) / 2.;
          else
            return cross_product_3d(a, b).norm() / 2.;
        }
      if constexpr (dim == 3)
        return std::abs(cross_product_3d(a, b) * (p[3] - p[0])) / 6.;
      return 0;
    }



    /// "[0, 1] x [0, 2]"
    template <int dim>
    std::string
    box_text(const typename DomainSummary<dim>::Part &part)
    {
      std::ostringstream text;
      text << std::setprecision(4);
      for (unsigned int d = 0; d < dim; ++d)
        text << (d > 0 ? " x [" : "[") << part.lower[d] << ", " << part.upper[d]
             << "]";
      return text.str();
    }



    std::string
    number_text(const double x)
    {
      std::ostringstream text;
      text << std::setprecision(4) << x;
      return text.str();
    }



    /// "{1, 2, 3}", 0 written "0 (no physical tag)"
    template <int dim>
    std::string
    ids_text(const std::map<types::boundary_id,
                            typename DomainSummary<dim>::Part> &parts)
    {
      std::string text;
      for (const auto &[id, part] : parts)
        text += (text.empty() ? "{" : ", ") + std::to_string(id) +
                (id == 0 ? " (no physical tag)" : "");
      return text + "}";
    }
  } // namespace



  template <int dim>
  DomainSummary<dim>::Part::Part()
  {
    for (unsigned int d = 0; d < dim; ++d)
      {
        lower[d] = std::numeric_limits<double>::max();
        upper[d] = -std::numeric_limits<double>::max();
      }
  }



  template <int dim>
  void
  DomainSummary<dim>::Part::add(const Point<dim> &point)
  {
    for (unsigned int d = 0; d < dim; ++d)
      {
        lower[d] = std::min(lower[d], point[d]);
        upper[d] = std::max(upper[d], point[d]);
      }
  }



  template <int dim>
  DomainSummary<dim>::DomainSummary(const std::vector<Point<dim>>    &vertices,
                                    const std::vector<CellData<dim>> &cells,
                                    const SubCellData &boundary_data)
  {
    using Face = std::array<unsigned int, dim>;
    // every face of every cell, sorted by its corners: neighbours are
    // adjacent
    std::vector<std::pair<Face, unsigned int>> faces;
    std::vector<Point<dim>>                    corners(dim + 1);
    for (unsigned int c = 0; c < cells.size(); ++c)
      {
        for (unsigned int v = 0; v <= dim; ++v)
          {
            corners[v] = vertices[cells[c].vertices[v]];
            domain.add(corners[v]);
          }
        domain.measure += simplex_measure(corners);
        for (unsigned int omitted = 0; omitted <= dim; ++omitted)
          {
            Face face;
            for (unsigned int v = 0, k = 0; v <= dim; ++v)
              if (v != omitted)
                face[k++] = cells[c].vertices[v];
            std::sort(face.begin(), face.end());
            faces.emplace_back(face, c);
          }
      }
    std::sort(faces.begin(), faces.end());

    std::map<Face, types::boundary_id> id_of;
    const auto                         tag = [&](const auto &elements) {
      for (const auto &element : elements)
        {
          Face face;
          for (unsigned int v = 0; v < dim; ++v)
            face[v] = element.vertices[v];
          std::sort(face.begin(), face.end());
          id_of[face] = element.boundary_id;
        }
    };
    if constexpr (dim == 2)
      tag(boundary_data.boundary_lines);
    else
      tag(boundary_data.boundary_quads);

    // bodies: cells joined through shared faces (union-find)
    std::vector<unsigned int> root(cells.size());
    std::iota(root.begin(), root.end(), 0);
    const auto find = [&](unsigned int c) {
      while (root[c] != c)
        c = root[c] = root[root[c]];
      return c;
    };
    std::vector<Point<dim>> face_corners(dim);
    for (unsigned int f = 0; f < faces.size();)
      {
        unsigned int next = f + 1;
        while (next < faces.size() && faces[next].first == faces[f].first)
          {
            root[find(faces[next].second)] = find(faces[f].second);
            ++next;
          }
        if (next == f + 1)
          {
            const auto entry = id_of.find(faces[f].first);
            Part &part = boundary[entry == id_of.end() ? 0 : entry->second];
            for (unsigned int v = 0; v < dim; ++v)
              {
                face_corners[v] = vertices[faces[f].first[v]];
                part.add(face_corners[v]);
              }
            part.measure += simplex_measure(face_corners);
          }
        f = next;
      }
    for (unsigned int c = 0; c < cells.size(); ++c)
      n_bodies += (find(c) == c);
  }



  template <int dim>
  std::string
  DomainSummary<dim>::difference_from(const DomainSummary &mesh,
                                      const double         tolerance) const
  {
    const double diameter     = (mesh.domain.upper - mesh.domain.lower).norm();
    const auto   boxes_differ = [&](const Part &a, const Part &b) {
      for (unsigned int d = 0; d < dim; ++d)
        if (std::abs(a.lower[d] - b.lower[d]) > tolerance * diameter ||
            std::abs(a.upper[d] - b.upper[d]) > tolerance * diameter)
          return true;
      return false;
    };
    const auto measures_differ = [&](const Part &a, const Part &b) {
      return std::abs(a.measure - b.measure) >
             tolerance * std::max(a.measure, b.measure);
    };
    const std::string measure = dim == 2 ? "area" : "volume";
    if (boxes_differ(domain, mesh.domain))
      return "its domain spans " + box_text<dim>(domain) + ", the mesh's " +
             box_text<dim>(mesh.domain);
    if (measures_differ(domain, mesh.domain))
      return "its domain has the " + measure + " " +
             number_text(domain.measure) + ", the mesh's " +
             number_text(mesh.domain.measure);
    bool same_ids = boundary.size() == mesh.boundary.size();
    for (const auto &[id, part] : boundary)
      same_ids = same_ids && mesh.boundary.count(id) == 1;
    if (!same_ids)
      return std::string("its boundary ids (physical ") +
             (dim == 2 ? "curves" : "surfaces") + ") are " +
             ids_text<dim>(boundary) + ", the mesh's " +
             ids_text<dim>(mesh.boundary);
    const std::string face_measure = dim == 2 ? "length" : "area";
    for (const auto &[id, part] : boundary)
      {
        const Part &other = mesh.boundary.at(id);
        if (measures_differ(part, other))
          return "its boundary id " + std::to_string(id) + " has the " +
                 face_measure + " " + number_text(part.measure) +
                 ", the mesh's " + number_text(other.measure);
        if (boxes_differ(part, other))
          return "its boundary id " + std::to_string(id) + " spans " +
                 box_text<dim>(part) + ", the mesh's " + box_text<dim>(other);
      }
    return "";
  }



  template class DomainSummary<2>;
  template class DomainSummary<3>;
} // namespace Signorini
