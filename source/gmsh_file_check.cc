#include <signorini/gmsh_file_check.h>
#include <signorini/input_error.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <unordered_map>

namespace Signorini
{
  namespace
  {
    /// Relative tolerance on distances: nodes closer than this times the
    /// diameter of the mesh are one point, and a triangle whose smallest
    /// height is below this times its longest edge is flat.
    constexpr double distance_tolerance = 1e-10;

    /// Relative tolerance on areas, times the squared diameter of the mesh.
    constexpr double area_tolerance = 1e-12;

    /// Relative tolerance on volumes, times the cubed diameter of the mesh.
    constexpr double volume_tolerance = 1e-18;

    /// The Gmsh element types signorini reads; any other is refused.
    enum ElementType : int
    {
      line_element        = 1,
      triangle_element    = 2,
      tetrahedron_element = 4,
      point_element       = 15
    };

    /// A printable excerpt of a line or token of the file for a message:
    /// bounded, on one line, without control or binary characters.
    std::string
    excerpt(const std::string &text)
    {
      const std::size_t max_length = 40;
      std::string       result     = "<";
      for (std::size_t i = 0; i < std::min(text.size(), max_length); ++i)
        result += (text[i] >= 32 && text[i] < 127) ? text[i] : '?';
      return result + (text.size() > max_length ? "...>" : ">");
    }

    /// "(x, y)" or "(x, y, z)" for messages.
    std::string
    coordinates(const std::array<double, 3> &x, const unsigned int dim = 2)
    {
      std::ostringstream out;
      out << "(" << x[0] << ", " << x[1];
      if (dim == 3)
        out << ", " << x[2];
      out << ")";
      return out.str();
    }

    /// Parse the whole of @p token as a decimal integer.
    bool
    parse_integer(const std::string &token, long long &value)
    {
      const std::size_t sign =
        (token.size() > 1 && (token[0] == '-' || token[0] == '+')) ? 1 : 0;
      if (token.size() == sign ||
          token.find_first_not_of("0123456789", sign) != std::string::npos)
        return false;
      errno     = 0;
      char *end = nullptr;
      value     = std::strtoll(token.c_str(), &end, 10);
      return errno == 0 && *end == '\0';
    }

    /// Parse the whole of @p token as a finite real; an underflow is zero.
    bool
    parse_real(const std::string &token, double &value)
    {
      // also refuses nan, inf and hexadecimal floats, which strtod takes
      if (token.empty() ||
          token.find_first_not_of("0123456789+-.eE") != std::string::npos)
        return false;
      errno     = 0;
      char *end = nullptr;
      value     = std::strtod(token.c_str(), &end);
      if (*end != '\0')
        return false;
      if (errno == ERANGE && std::abs(value) <= DBL_MIN)
        value = 0.; // a coordinate below 1e-308 is zero
      else if (errno != 0)
        return false;
      return std::isfinite(value);
    }

    /// A node of the file: its Gmsh tag, coordinates and line.
    struct Node
    {
      long long             tag;
      std::array<double, 3> x;
      unsigned int          line;
    };

    /// A cell (triangle in 2D, tetrahedron in 3D) or boundary element (line
    /// in 2D, triangle in 3D) of the file: its Gmsh tag, line, physical tag
    /// and nodes (indices into the list of nodes; the first 2, 3 or 4 used).
    struct Element
    {
      long long                   tag;
      unsigned int                line;
      long long                   physical;
      std::array<unsigned int, 4> nodes;
    };

    /// Disjoint sets of cells (union-find with path halving).
    class UnionFind
    {
    public:
      explicit UnionFind(const unsigned int n)
        : parent(n)
      {
        for (unsigned int i = 0; i < n; ++i)
          parent[i] = i;
      }

      unsigned int
      root(unsigned int i)
      {
        while (parent[i] != i)
          i = parent[i] = parent[parent[i]];
        return i;
      }

      void
      join(const unsigned int i, const unsigned int j)
      {
        parent[root(i)] = root(j);
      }

      unsigned int
      size() const
      {
        return parent.size();
      }

    private:
      std::vector<unsigned int> parent;
    };

    /**
     * The strict parser. It walks through the file line by line (blank
     * lines and $Comments sections are skipped, as deal.II does), and every
     * record must be on one line with exactly the numbers the format asks
     * for. Counts are only compared with the records actually present,
     * never used to allocate memory, so a huge count cannot exhaust it.
     */
    class GmshParser
    {
    public:
      GmshParser(const std::string &path,
                 const std::string &text,
                 const unsigned int dim)
        : path(path)
        , text(text)
        , dim(dim)
        , cell_type(dim == 2 ? triangle_element : tetrahedron_element)
        , face_type(dim == 2 ? line_element : triangle_element)
      {}

      /// Parse the whole file (of a mesh of dimension dim).
      void
      parse();

      /// The geometric checks of a mesh of triangles, and the mesh.
      GmshMesh<2>
      check_triangles() const;

      /// The geometric checks of a mesh of tetrahedra, and the mesh.
      GmshMesh<3>
      check_tetrahedra() const;

    private:
      const std::string &path;
      const std::string &text;

      /// 2: a mesh of triangles, 3: of tetrahedra.
      const unsigned int dim;

      /// The Gmsh types of the cells and of their faces.
      const ElementType cell_type, face_type;

      /// Start of the next line in text.
      std::size_t position = 0;

      /// Number (1-based) of the current line, 0 before the first.
      unsigned int line_number = 0;

      /// The current line without surrounding blanks, and its tokens.
      std::string              line;
      std::vector<std::string> tokens;

      /// 20, 21, 22 (msh 2.x), 40 or 41.
      int version = 0;

      /// Physical tag (0 if none) of each entity (dimension, tag) declared
      /// in $Entities.
      std::map<std::pair<long long, long long>, long long> entities;

      /// Whether the file has an $Entities section.
      bool have_entities = false;

      /// The nodes in file order, and the index of each tag among them.
      std::vector<Node>                           nodes;
      std::unordered_map<long long, unsigned int> node_index;

      /// The cells (triangles in 2D, tetrahedra in 3D) and the elements of
      /// their faces (lines in 2D, triangles in 3D), in file order.
      std::vector<Element> cells;
      std::vector<Element> faces;

      [[noreturn]] void
      fail_at(const unsigned int at, const std::string &what) const
      {
        throw InputError("cannot read mesh file <" + path + ">: line " +
                         std::to_string(at) + ": " + what);
      }

      [[noreturn]] void
      fail(const std::string &what) const
      {
        fail_at(line_number, what);
      }

      /// A geometric defect: the file was read, the mesh is unusable.
      [[noreturn]] void
      reject_at(const unsigned int at, const std::string &what) const
      {
        throw InputError("<" + path + ">: line " + std::to_string(at) + ": " +
                         what);
      }

      /// Move to the next non-blank line; false at the end of the file.
      bool
      next_raw_line();

      /// Move to the next line that is neither blank nor in a $Comments
      /// section and split it; false at the end of the file.
      bool
      advance();

      /// Move to the next line, which must exist: @p expected says what the
      /// format asks for there (for the message about a truncated file).
      void
      next(const std::string &expected);

      /// Move to the next line, which must be the record @p what (not a
      /// section marker: then a count said more records than there are).
      void
      record(const std::string &what);

      /// The next line must be exactly @p marker.
      void
      expect_marker(const std::string &marker);

      /// The current line must have exactly @p n tokens.
      void
      expect_tokens(const std::size_t n, const std::string &what) const;

      /// Token @p i of the current line as an integer in [min, max].
      long long
      integer(const std::size_t  i,
              const std::string &what,
              const long long    min = LLONG_MIN,
              const long long    max = LLONG_MAX) const;

      /// Token 0 of the current line as the tag of a @p kind ("node" or
      /// "element"), in the range [@p min, @p max] of the section header.
      long long
      tag_in_range(const std::string &kind,
                   const long long    min,
                   const long long    max) const;

      /// Token @p i of the current line as a finite real.
      double
      real(const std::size_t i, const std::string &what) const;

      void
      parse_header();

      void
      parse_physical_names();

      void
      parse_entities();

      void
      parse_nodes();

      void
      parse_elements();

      /// Skip a section this reader does not use, checking it is closed.
      void
      skip_section();

      /// Store a node of tag @p tag whose coordinates are the tokens of the
      /// current line from @p first on.
      void
      add_node(const long long tag, const std::size_t first);

      /// Store an element of @p type whose tag is token 0 of the current
      /// line and whose nodes are its tokens from @p first on.
      void
      add_element(const long long   type,
                  const long long   physical,
                  const std::size_t first);

      /// Number of nodes of an element of the Gmsh @p type, checking the
      /// type is one signorini reads.
      unsigned int
      nodes_per_element(const long long type) const;

      /// The physical tag of the entity (@p dim, @p tag) of an element block
      /// of msh 4; the entity must be declared if $Entities is present.
      long long
      entity_physical_tag(const long long dim, const long long tag) const;

      /// The checks common to both dimensions: the nodes the cells use
      /// (@p used, in file order; @p vertex: the index among them of each
      /// node, or -1), the bounding box (@p low, @p high) and its
      /// @p diameter, the range of the coordinates, a flat mesh in 2D and no
      /// two nodes at the same point.
      void
      check_nodes(std::vector<unsigned int> &vertex,
                  std::vector<unsigned int> &used,
                  std::array<double, 3>     &low,
                  std::array<double, 3>     &high,
                  double                    &diameter) const;

      /// Fail unless the cells are one body, connected through the shared
      /// faces of @p faces (each face's side[] names the cells on either
      /// side, -1 for none): a second part would float free in the solver.
      template <typename FaceMap>
      void
      check_one_body(const FaceMap &faces) const;
    };



    bool
    GmshParser::next_raw_line()
    {
      const char *const blanks = " \t\r\f\v";
      while (position < text.size())
        {
          std::size_t end = text.find('\n', position);
          if (end == std::string::npos)
            end = text.size();
          ++line_number;
          const std::size_t begin = text.find_first_not_of(blanks, position);
          const std::size_t last  = end > position ?
                                      text.find_last_not_of(blanks, end - 1) :
                                      std::string::npos;
          position                = end + 1;
          if (begin < end && last != std::string::npos && last >= begin)
            {
              line = text.substr(begin, last + 1 - begin);
              return true;
            }
        }
      return false;
    }



    bool
    GmshParser::advance()
    {
      if (!next_raw_line())
        return false;
      while (line == "$Comments")
        {
          // deal.II drops comment sections wherever they are
          const unsigned int start = line_number;
          do
            if (!next_raw_line())
              fail_at(start, "$Comments is not closed by $EndComments");
          while (line != "$EndComments");
          if (!next_raw_line())
            return false;
        }
      tokens.clear();
      std::size_t begin = 0;
      while ((begin = line.find_first_not_of(" \t\r\f\v", begin)) !=
             std::string::npos)
        {
          const std::size_t end = line.find_first_of(" \t\r\f\v", begin);
          tokens.push_back(line.substr(begin, end - begin));
          begin = end;
        }
      return true;
    }



    void
    GmshParser::next(const std::string &expected)
    {
      if (!advance())
        fail("the file ends where " + expected +
             " was expected (is it truncated?)");
    }



    void
    GmshParser::record(const std::string &what)
    {
      next(what);
      if (line[0] == '$')
        fail("found " + excerpt(line) + " where " + what +
             " was expected (a count in the file is larger than the number "
             "of records present)");
    }



    void
    GmshParser::expect_marker(const std::string &marker)
    {
      next(marker);
      if (line != marker)
        fail("expected " + marker + ", found " + excerpt(line) +
             (line[0] == '$' ? std::string() :
                               " (a count in the file is smaller than the "
                               "number of records present?)"));
    }



    void
    GmshParser::expect_tokens(const std::size_t  n,
                              const std::string &what) const
    {
      if (tokens.size() != n)
        fail(what + " " + excerpt(line) + " has " +
             std::to_string(tokens.size()) +
             (tokens.size() == 1 ? " field" : " fields") + ", expected " +
             std::to_string(n));
    }



    long long
    GmshParser::integer(const std::size_t  i,
                        const std::string &what,
                        const long long    min,
                        const long long    max) const
    {
      if (i >= tokens.size())
        fail("missing " + what + " in " + excerpt(line));
      long long value = 0;
      if (!parse_integer(tokens[i], value))
        fail(what + " " + excerpt(tokens[i]) + " is not an integer");
      if (value < min)
        fail(what + " " + tokens[i] + " is below " + std::to_string(min));
      if (value > max)
        fail(what + " " + tokens[i] + " is above " + std::to_string(max));
      return value;
    }



    long long
    GmshParser::tag_in_range(const std::string &kind,
                             const long long    min,
                             const long long    max) const
    {
      const long long tag = integer(0, kind + " tag", 1);
      if (tag < min || tag > max)
        fail(kind + " tag " + std::to_string(tag) + " is outside the range [" +
             std::to_string(min) + ", " + std::to_string(max) +
             "] the section header announces");
      return tag;
    }



    double
    GmshParser::real(const std::size_t i, const std::string &what) const
    {
      if (i >= tokens.size())
        fail("missing " + what + " in " + excerpt(line));
      double value = 0;
      if (!parse_real(tokens[i], value))
        fail(what + " " + excerpt(tokens[i]) + " is not a finite number");
      return value;
    }



    void
    GmshParser::parse_header()
    {
      if (!advance())
        throw InputError("<" + path + "> is empty");
      if (line == "$NOD")
        fail("this is an msh 1 file; save the mesh as msh 2.2 or 4.1");
      if (line != "$MeshFormat")
        fail("expected $MeshFormat, found " + excerpt(line) +
             " (is this a Gmsh mesh file?)");
      next("the version line of $MeshFormat");
      if (tokens.size() != 3)
        fail("expected \"version file-type data-size\" after $MeshFormat, "
             "found " +
             excerpt(line));
      const std::string &v = tokens[0];
      if (v == "2" || v == "2.0")
        version = 20;
      else if (v == "2.1")
        version = 21;
      else if (v == "2.2")
        version = 22;
      else if (v == "4" || v == "4.0")
        version = 40;
      else if (v == "4.1")
        version = 41;
      else
        fail("Gmsh format version " + excerpt(v) +
             " is not supported; save the mesh as msh 2.2 or 4.1");
      if (tokens[1] == "1")
        throw InputError(
          "<" + path + "> is a binary Gmsh file; save it as ASCII (gmsh " +
          path + " -save -format msh41 -o ascii.msh, or Mesh.Binary = 0)");
      if (tokens[1] != "0")
        fail("file type " + excerpt(tokens[1]) + " is neither 0 (ASCII) nor 1");
      if (tokens[2] != "8")
        fail("data size " + excerpt(tokens[2]) +
             " is not 8 (the size of a double)");
      expect_marker("$EndMeshFormat");
    }



    void
    GmshParser::parse_physical_names()
    {
      next("the number of physical names");
      expect_tokens(1, "the number of physical names");
      const long long n = integer(0, "number of physical names", 0);
      for (long long i = 0; i < n; ++i)
        {
          const std::string what = "physical name " + std::to_string(i + 1) +
                                   " of " + std::to_string(n);
          record(what);
          integer(0, "dimension of a physical name", 0, 3);
          integer(1, "tag of a physical name");
          // the name is quoted and may contain blanks
          const std::size_t quote = line.find('"');
          if (tokens.size() < 3 || tokens[2][0] != '"' ||
              quote == line.size() - 1 || line.back() != '"')
            fail(what + " " + excerpt(line) +
                 " is not \"dimension tag \"name\"\"");
        }
      expect_marker("$EndPhysicalNames");
    }



    void
    GmshParser::parse_entities()
    {
      have_entities = true;
      next("the numbers of points, curves, surfaces and volumes");
      expect_tokens(4, "the numbers of entities");
      std::array<long long, 4> n;
      for (unsigned int d = 0; d < 4; ++d)
        n[d] = integer(d, "number of entities", 0);
      const char *const kind[4] = {"point", "curve", "surface", "volume"};
      for (unsigned int d = 0; d < 4; ++d)
        for (long long i = 0; i < n[d]; ++i)
          {
            const std::string what = std::string(kind[d]) + " " +
                                     std::to_string(i + 1) + " of " +
                                     std::to_string(n[d]) + " in $Entities";
            record(what);
            const long long tag = integer(0, std::string(kind[d]) + " tag");
            // points of msh 4.1 have one position, everything else a box
            const std::size_t n_reals = (d == 0 && version == 41) ? 3 : 6;
            for (std::size_t j = 1; j <= n_reals; ++j)
              real(j, std::string("bounding box of ") + kind[d]);
            const std::size_t n_physicals_at = n_reals + 1;
            const long long   n_physicals =
              integer(n_physicals_at, "number of physical tags", 0);
            if (n_physicals > static_cast<long long>(tokens.size()))
              fail(what + ": " + std::to_string(n_physicals) +
                   " physical tags announced, fewer present");
            std::size_t expected = n_physicals_at + 1 + n_physicals;
            if (d > 0)
              {
                const long long n_bounding =
                  integer(expected, "number of bounding entities", 0);
                if (n_bounding > static_cast<long long>(tokens.size()))
                  fail(what + ": " + std::to_string(n_bounding) +
                       " bounding entities announced, fewer present");
                for (long long j = 0; j < n_bounding; ++j)
                  integer(expected + 1 + j, "bounding entity tag");
                expected += 1 + n_bounding;
              }
            expect_tokens(expected, what);
            // the physical tag of an entity of the faces' dimension is its
            // boundary id, of the cells' its material id: one at most, as in
            // deal.II; entities of lower dimensions play no role
            const bool tagged = (d + 1 == dim || d == dim);
            if (n_physicals > 1 && tagged)
              fail(std::string(kind[d]) + " " + std::to_string(tag) +
                   " belongs to " + std::to_string(n_physicals) +
                   " physical groups; signorini takes at most one per " +
                   kind[d]);
            long long physical = 0;
            for (long long j = 0; j < n_physicals; ++j)
              physical =
                tagged ?
                  integer(n_physicals_at + 1 + j, "physical tag", 0, INT_MAX) :
                  integer(n_physicals_at + 1 + j, "physical tag");
            if (!entities.emplace(std::make_pair(d, tag), physical).second)
              fail(std::string(kind[d]) + " " + std::to_string(tag) +
                   " is declared twice");
          }
      expect_marker("$EndEntities");
    }



    void
    GmshParser::add_node(const long long tag, const std::size_t first)
    {
      Node node;
      node.tag  = tag;
      node.line = line_number;
      for (unsigned int d = 0; d < 3; ++d)
        node.x[d] =
          real(first + d, "coordinate of node " + std::to_string(tag));
      if (!node_index.emplace(tag, nodes.size()).second)
        fail("node " + std::to_string(tag) +
             " is defined twice (first on line " +
             std::to_string(nodes[node_index[tag]].line) + ")");
      nodes.push_back(node);
    }



    void
    GmshParser::parse_nodes()
    {
      if (version < 40)
        {
          next("the number of nodes");
          expect_tokens(1, "the number of nodes");
          const long long n = integer(0, "number of nodes", 0);
          for (long long i = 0; i < n; ++i)
            {
              const std::string what =
                "node " + std::to_string(i + 1) + " of " + std::to_string(n);
              record(what);
              expect_tokens(4, what + " (tag x y z)");
              add_node(integer(0, "node tag", 1), 1);
            }
          expect_marker("$EndNodes");
          return;
        }

      next("the header of $Nodes");
      expect_tokens(version == 41 ? 4 : 2, "the header of $Nodes");
      const long long n_blocks = integer(0, "number of node blocks", 0);
      const long long n_nodes  = integer(1, "number of nodes", 0);
      long long       min_tag = 0, max_tag = LLONG_MAX;
      if (version == 41)
        {
          min_tag = integer(2, "smallest node tag", 0);
          max_tag = integer(3, "largest node tag", 0);
        }
      const unsigned int header_line = line_number;
      long long          n_read      = 0;
      for (long long b = 0; b < n_blocks; ++b)
        {
          const std::string block = "node block " + std::to_string(b + 1) +
                                    " of " + std::to_string(n_blocks);
          record("the header of " + block);
          expect_tokens(4, "the header of " + block);
          // 4.1: dimension, tag; 4.0: tag, dimension
          integer(version == 41 ? 0 : 1, "entity dimension", 0, 3);
          integer(version == 41 ? 1 : 0, "entity tag");
          const long long parametric = integer(2, "parametric flag", 0, 1);
          if (parametric != 0)
            fail(block + " has parametric coordinates, which are not "
                         "supported; save the mesh without them "
                         "(Mesh.SaveParametric = 0)");
          const long long n = integer(3, "number of nodes in the block", 0);
          if (n > n_nodes - n_read)
            fail(block + " has " + std::to_string(n) +
                 " nodes, but $Nodes announces " + std::to_string(n_nodes) +
                 " in all and " + std::to_string(n_read) + " came before");
          if (version == 40)
            for (long long i = 0; i < n; ++i)
              {
                const std::string what = "node " + std::to_string(i + 1) +
                                         " of " + std::to_string(n) + " of " +
                                         block;
                record(what);
                expect_tokens(4, what + " (tag x y z)");
                add_node(tag_in_range("node", min_tag, max_tag), 1);
              }
          else
            {
              // n tags, then n coordinate lines
              std::vector<long long> block_tags;
              for (long long i = 0; i < n; ++i)
                {
                  const std::string what = "tag of node " +
                                           std::to_string(i + 1) + " of " +
                                           std::to_string(n) + " of " + block;
                  record(what);
                  expect_tokens(1, what);
                  block_tags.push_back(tag_in_range("node", min_tag, max_tag));
                }
              for (long long i = 0; i < n; ++i)
                {
                  const std::string what =
                    "coordinates of node " + std::to_string(block_tags[i]) +
                    " (" + std::to_string(i + 1) + " of " + std::to_string(n) +
                    " of " + block + ")";
                  record(what);
                  expect_tokens(3, what);
                  add_node(block_tags[i], 0);
                }
            }
          n_read += n;
        }
      if (n_read != n_nodes)
        fail_at(header_line,
                "$Nodes announces " + std::to_string(n_nodes) +
                  " nodes, its blocks hold " + std::to_string(n_read));
      expect_marker("$EndNodes");
    }



    unsigned int
    GmshParser::nodes_per_element(const long long type) const
    {
      const std::string needed =
        dim == 2 ? "a mesh of 3-node triangles" :
                   "a mesh of 4-node tetrahedra (with 3-node triangles on "
                   "its boundary)";
      switch (type)
        {
          case point_element:
            return 1;
          case line_element:
            return 2;
          case triangle_element:
            return 3;
          case tetrahedron_element:
            if (dim == 3)
              return 4;
            fail("tetrahedra (type 4) are 3D elements: signorini reads them "
                 "with Dimension = 3; in 2D it needs a mesh of triangles");
          case 3:
          case 16:
          case 10:
            fail("quadrilateral elements (type " + std::to_string(type) +
                 ") are not supported: signorini needs " + needed +
                 " (do not recombine)");
          case 5:
          case 6:
          case 7:
          case 12:
          case 13:
          case 14:
          case 17:
          case 18:
          case 19:
            fail("hexahedra, prisms and pyramids (type " +
                 std::to_string(type) +
                 ") are not supported: signorini "
                 "needs " +
                 needed);
          case 8:
          case 9:
          case 11:
          case 20:
          case 21:
          case 22:
          case 23:
          case 24:
          case 25:
          case 26:
          case 27:
          case 28:
            fail("high-order elements (type " + std::to_string(type) +
                 ") are not supported: save a first-order mesh "
                 "(gmsh -order 1); signorini needs " +
                 needed);
          default:
            fail("element type " + std::to_string(type) +
                 " is not supported: signorini reads " +
                 (dim == 2 ? "3-node triangles (type 2), 2-node lines (1) "
                             "and points (15)" :
                             "4-node tetrahedra (type 4), 3-node triangles "
                             "(2), 2-node lines (1) and points (15)"));
        }
    }



    void
    GmshParser::add_element(const long long   type,
                            const long long   physical,
                            const std::size_t first)
    {
      Element element;
      element.tag          = integer(0, "element tag", 1);
      element.line         = line_number;
      element.physical     = physical;
      element.nodes        = {{0, 0, 0, 0}};
      const unsigned int n = nodes_per_element(type);
      for (unsigned int v = 0; v < n; ++v)
        {
          const long long tag = integer(first + v, "node tag", 1);
          const auto      p   = node_index.find(tag);
          if (p == node_index.end())
            fail("element " + std::to_string(element.tag) + " refers to node " +
                 std::to_string(tag) + ", which is not in $Nodes");
          element.nodes[v] = p->second;
          for (unsigned int w = 0; w < v; ++w)
            if (element.nodes[w] == p->second)
              fail("element " + std::to_string(element.tag) + " uses node " +
                   std::to_string(tag) + " twice");
        }
      // lower-dimensional elements (points; lines in 3D) carry nothing
      if (type == cell_type)
        cells.push_back(element);
      else if (type == face_type)
        faces.push_back(element);
    }



    long long
    GmshParser::entity_physical_tag(const long long dim,
                                    const long long tag) const
    {
      const auto p = entities.find(std::make_pair(dim, tag));
      if (p != entities.end())
        return p->second;
      if (have_entities)
        fail("the element block refers to entity " + std::to_string(tag) +
             " of dimension " + std::to_string(dim) +
             ", which is not in $Entities");
      return 0;
    }



    void
    GmshParser::parse_elements()
    {
      if (version < 40)
        {
          next("the number of elements");
          expect_tokens(1, "the number of elements");
          const long long n = integer(0, "number of elements", 0);
          for (long long i = 0; i < n; ++i)
            {
              const std::string what =
                "element " + std::to_string(i + 1) + " of " + std::to_string(n);
              record(what);
              // tag type number-of-tags tags... nodes...
              const long long type = integer(1, "element type");
              const long long n_tags =
                integer(2, "number of element tags", 0, 1000);
              const unsigned int n_nodes = nodes_per_element(type);
              expect_tokens(3 + n_tags + n_nodes, what);
              const long long tag = integer(0, "element tag", 1);
              for (long long j = 0; j < n_tags; ++j)
                integer(3 + j,
                        "tag " + std::to_string(j + 1) + " of element " +
                          std::to_string(tag));
              long long physical = 0;
              if (n_tags > 0 && type != point_element)
                physical = integer(3, "physical tag", 0, INT_MAX);
              add_element(type, physical, 3 + n_tags);
            }
          expect_marker("$EndElements");
          return;
        }

      next("the header of $Elements");
      expect_tokens(version == 41 ? 4 : 2, "the header of $Elements");
      const long long n_blocks   = integer(0, "number of element blocks", 0);
      const long long n_elements = integer(1, "number of elements", 0);
      long long       min_tag = 0, max_tag = LLONG_MAX;
      if (version == 41)
        {
          min_tag = integer(2, "smallest element tag", 0);
          max_tag = integer(3, "largest element tag", 0);
        }
      const unsigned int header_line = line_number;
      long long          n_read      = 0;
      for (long long b = 0; b < n_blocks; ++b)
        {
          const std::string block = "element block " + std::to_string(b + 1) +
                                    " of " + std::to_string(n_blocks);
          record("the header of " + block);
          expect_tokens(4, "the header of " + block);
          // 4.1: dimension, tag; 4.0: tag, dimension
          const long long dim =
            integer(version == 41 ? 0 : 1, "entity dimension", 0, 3);
          const long long entity = integer(version == 41 ? 1 : 0, "entity tag");
          const long long type   = integer(2, "element type");
          const long long n      = integer(3, "number of elements", 0);
          const unsigned int n_nodes  = nodes_per_element(type);
          const long long    type_dim = type == point_element    ? 0 :
                                        type == line_element     ? 1 :
                                        type == triangle_element ? 2 :
                                                                   3;
          if (dim != type_dim)
            fail(block + " puts elements of type " + std::to_string(type) +
                 " on an entity of dimension " + std::to_string(dim));
          const long long physical = entity_physical_tag(dim, entity);
          if (n > n_elements - n_read)
            fail(block + " has " + std::to_string(n) +
                 " elements, but $Elements announces " +
                 std::to_string(n_elements) + " in all and " +
                 std::to_string(n_read) + " came before");
          for (long long i = 0; i < n; ++i)
            {
              const std::string what = "element " + std::to_string(i + 1) +
                                       " of " + std::to_string(n) + " of " +
                                       block;
              record(what);
              expect_tokens(1 + n_nodes, what);
              tag_in_range("element", min_tag, max_tag);
              add_element(type, physical, 1);
            }
          n_read += n;
        }
      if (n_read != n_elements)
        fail_at(header_line,
                "$Elements announces " + std::to_string(n_elements) +
                  " elements, its blocks hold " + std::to_string(n_read));
      expect_marker("$EndElements");
    }



    void
    GmshParser::skip_section()
    {
      const std::string  end   = "$End" + line.substr(1);
      const unsigned int start = line_number;
      const std::string  name  = line;
      do
        if (!advance())
          fail_at(start,
                  excerpt(name) + " is not closed by " + excerpt(end) +
                    " (is the file truncated?)");
      while (line != end);
    }



    void
    GmshParser::parse()
    {
      parse_header();

      // deal.II's order: optional $PhysicalNames and $Entities, then $Nodes
      // and $Elements; other sections may only follow.
      bool have_names = false, have_nodes = false, have_elements = false;
      while (advance())
        {
          if (line[0] != '$')
            fail("expected a section ($Name), found " + excerpt(line));
          const bool before_nodes = !have_nodes;
          if (line == "$PhysicalNames" && before_nodes && !have_names &&
              !have_entities)
            {
              have_names = true;
              parse_physical_names();
            }
          else if (line == "$Entities" && before_nodes && !have_entities &&
                   version >= 40)
            parse_entities();
          else if (line == "$PartitionedEntities")
            fail("partitioned meshes are not supported; save the mesh "
                 "without partitions");
          else if (line == "$Nodes" && before_nodes)
            {
              have_nodes = true;
              parse_nodes();
              expect_marker("$Elements");
              parse_elements();
              have_elements = true;
            }
          else if (line.rfind("$End", 0) == 0)
            fail(excerpt(line) + " closes no open section");
          else if (before_nodes || line == "$Nodes" || line == "$Elements" ||
                   line == "$Entities" || line == "$PhysicalNames")
            fail("section " + excerpt(line) +
                 (have_nodes ? " is repeated or after $Elements" :
                               " is not supported before $Nodes"));
          else
            skip_section();
        }
      if (!have_elements)
        fail("the file ends before " +
             std::string(have_nodes ? "$Elements" : "$Nodes") +
             " (is it truncated?)");
    }



    void
    GmshParser::check_nodes(std::vector<unsigned int> &vertex,
                            std::vector<unsigned int> &used,
                            std::array<double, 3>     &low,
                            std::array<double, 3>     &high,
                            double                    &diameter) const
    {
      if (cells.empty())
        throw InputError(
          "<" + path + "> contains no " +
          (dim == 2 ? "triangles (Gmsh type 2): signorini needs a 2D mesh of "
                      "3-node triangles" :
                      "tetrahedra (Gmsh type 4): with Dimension = 3 signorini "
                      "needs a 3D mesh of 4-node tetrahedra"));
      const std::string cell_name = dim == 2 ? "triangles" : "tetrahedra";

      // The nodes used by the cells, renumbered in file order.
      const unsigned int unused = static_cast<unsigned int>(-1);
      vertex.assign(nodes.size(), unused);
      for (const Element &c : cells)
        for (unsigned int k = 0; k <= dim; ++k)
          vertex[c.nodes[k]] = 0;
      used.clear();
      for (unsigned int n = 0; n < nodes.size(); ++n)
        if (vertex[n] != unused)
          {
            vertex[n] = used.size();
            used.push_back(n);
          }

      // Size of the mesh: its bounding box diameter.
      low = nodes[used[0]].x, high = low;
      for (const unsigned int n : used)
        for (unsigned int d = 0; d < 3; ++d)
          {
            low[d]  = std::min(low[d], nodes[n].x[d]);
            high[d] = std::max(high[d], nodes[n].x[d]);
          }
      diameter =
        std::hypot(high[0] - low[0], high[1] - low[1], high[2] - low[2]);
      if (diameter == 0.)
        throw InputError("<" + path + ">: all nodes of the " + cell_name +
                         " are at the point " + coordinates(low, dim));
      // Extreme scales: areas and squared lengths would underflow or
      // overflow in the assembly and the checks.
      if (!std::isfinite(diameter) || diameter > 1e100 || diameter < 1e-100)
        {
          std::ostringstream message;
          message << "<" << path << ">: the mesh is " << diameter
                  << " across, outside [1e-100, 1e100]: change the units";
          throw InputError(message.str());
        }
      for (const unsigned int n : used)
        for (unsigned int d = 0; d < 3; ++d)
          if (std::abs(nodes[n].x[d]) > 1e150)
            {
              std::ostringstream message;
              message << "node " << nodes[n].tag << " has the coordinate "
                      << nodes[n].x[d]
                      << ", beyond 1e150 in absolute value (its square "
                         "overflows): change the units or the origin";
              reject_at(nodes[n].line, message.str());
            }

      // In 2D, a flat mesh in a plane z = const: its z is dropped.
      const double tolerance = distance_tolerance * diameter;
      const Node  &first     = nodes[used[0]];
      for (const unsigned int n : used)
        if (dim == 2 && std::abs(nodes[n].x[2] - first.x[2]) > tolerance)
          {
            std::ostringstream message;
            message << "node " << nodes[n].tag << " has z = " << nodes[n].x[2]
                    << " while node " << first.tag << " has z = " << first.x[2]
                    << ": signorini needs a flat mesh in a plane z = const "
                       "(a 3D mesh needs Dimension = 3)";
            reject_at(nodes[n].line, message.str());
          }

      // Coincident nodes, found by hashing the points into cells of the
      // size of the tolerance and comparing neighbouring cells only.
      const auto cell_of = [&](const Node &node, const unsigned int d) {
        return d < dim ? static_cast<long long>(
                           std::floor((node.x[d] - low[d]) / tolerance)) :
                         0LL;
      };
      const auto key =
        [](const long long i, const long long j, const long long k) {
          return (static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ULL ^
                  static_cast<std::uint64_t>(j)) *
                   0xC2B2AE3D27D4EB4FULL ^
                 static_cast<std::uint64_t>(k);
        };
      const long long reach = dim == 3 ? 1 : 0;
      std::unordered_multimap<std::uint64_t, unsigned int> grid;
      grid.reserve(used.size());
      for (const unsigned int n : used)
        {
          const long long i = cell_of(nodes[n], 0), j = cell_of(nodes[n], 1),
                          k = cell_of(nodes[n], 2);
          for (long long di = -1; di <= 1; ++di)
            for (long long dj = -1; dj <= 1; ++dj)
              for (long long dk = -reach; dk <= reach; ++dk)
                {
                  const auto range =
                    grid.equal_range(key(i + di, j + dj, k + dk));
                  for (auto p = range.first; p != range.second; ++p)
                    {
                      const Node  &other = nodes[p->second];
                      const double distance =
                        std::hypot(nodes[n].x[0] - other.x[0],
                                   nodes[n].x[1] - other.x[1],
                                   dim == 3 ? nodes[n].x[2] - other.x[2] : 0.);
                      if (distance <= tolerance)
                        reject_at(nodes[n].line,
                                  "nodes " + std::to_string(other.tag) +
                                    " and " + std::to_string(nodes[n].tag) +
                                    " are at the same point " +
                                    coordinates(nodes[n].x, dim) +
                                    ": the mesh would have a crack or a "
                                    "collapsed cell there; merge them");
                    }
                }
          grid.emplace(key(i, j, k), n);
        }
    }



    template <typename FaceMap>
    void
    GmshParser::check_one_body(const FaceMap &faces) const
    {
      UnionFind parts(cells.size());
      for (const auto &face : faces)
        if (face.second.side[0] >= 0 && face.second.side[1] >= 0)
          parts.join(face.second.side[0], face.second.side[1]);
      unsigned int n_parts = 0, second = 0;
      for (unsigned int c = 0; c < parts.size(); ++c)
        if (parts.root(c) == c)
          ++n_parts;
      if (n_parts < 2)
        return;
      for (unsigned int c = 0; c < parts.size(); ++c)
        if (parts.root(c) != parts.root(0))
          {
            second = c;
            break;
          }
      std::array<double, 3> centre = {{0, 0, 0}};
      for (unsigned int k = 0; k <= dim; ++k)
        for (unsigned int d = 0; d < dim; ++d)
          centre[d] += nodes[cells[second].nodes[k]].x[d] / (dim + 1);
      throw InputError("<" + path + "> has " + std::to_string(n_parts) +
                       " separate parts (one body is modelled); part 2 "
                       "contains the " +
                       (dim == 2 ? "triangle " : "tetrahedron ") +
                       std::to_string(cells[second].tag) + " at " +
                       coordinates(centre, dim));
    }



    GmshMesh<2>
    GmshParser::check_triangles() const
    {
      std::vector<unsigned int> vertex, used;
      std::array<double, 3>     low, high;
      double                    diameter;
      check_nodes(vertex, used, low, high, diameter);
      const double                tolerance = distance_tolerance * diameter;
      const std::vector<Element> &triangles = cells;
      const std::vector<Element> &lines     = faces;

      // Triangles of (nearly) zero area, and the orientation of the others.
      GmshMesh<2>       mesh;
      std::vector<bool> clockwise(triangles.size());
      for (unsigned int t = 0; t < triangles.size(); ++t)
        {
          const Element &triangle = triangles[t];
          // in units of the diameter, so that nothing overflows
          std::array<std::array<double, 2>, 3> e;
          for (unsigned int k = 0; k < 3; ++k)
            for (unsigned int d = 0; d < 2; ++d)
              e[k][d] = (nodes[triangle.nodes[(k + 1) % 3]].x[d] -
                         nodes[triangle.nodes[k]].x[d]) /
                        diameter;
          const double twice_area = e[0][0] * e[1][1] - e[0][1] * e[1][0];
          double       longest    = 0;
          for (unsigned int k = 0; k < 3; ++k)
            longest = std::max(longest, std::hypot(e[k][0], e[k][1]));
          if (std::abs(twice_area) <= 2 * area_tolerance ||
              std::abs(twice_area) <= distance_tolerance * longest * longest)
            {
              std::ostringstream message;
              const double       area = std::abs(twice_area) / 2;
              message << "triangle " << triangle.tag;
              if (area == 0.)
                message << " has zero area";
              else
                message << " has nearly zero area "
                        << area * diameter * diameter;
              message << ": its nodes";
              for (unsigned int k = 0; k < 3; ++k)
                message << (k > 0 ? ", " : " ") << nodes[triangle.nodes[k]].tag
                        << " " << coordinates(nodes[triangle.nodes[k]].x);
              message << " are " << (area == 0. ? "" : "nearly ")
                      << "collinear";
              reject_at(triangle.line, message.str());
            }
          clockwise[t] = twice_area < 0;
        }

      // Each edge borders at most two triangles, one on each side (after
      // orienting them counterclockwise): otherwise triangles overlap.
      struct EdgeTriangles
      {
        // triangle (index) on each side, -1 if none
        std::array<int, 2> side = {{-1, -1}};
      };
      std::unordered_map<std::uint64_t, EdgeTriangles> edges;
      edges.reserve(3 * triangles.size());
      const auto edge_key = [&](const unsigned int a, const unsigned int b) {
        return (static_cast<std::uint64_t>(std::min(vertex[a], vertex[b]))
                << 32) |
               std::max(vertex[a], vertex[b]);
      };
      for (unsigned int t = 0; t < triangles.size(); ++t)
        {
          const Element &triangle = triangles[t];
          for (unsigned int k = 0; k < 3; ++k)
            {
              unsigned int a = triangle.nodes[k],
                           b = triangle.nodes[(k + 1) % 3];
              if (clockwise[t])
                std::swap(a, b);
              const unsigned int side = vertex[a] < vertex[b] ? 0 : 1;
              EdgeTriangles     &edge = edges[edge_key(a, b)];
              if (edge.side[side] >= 0)
                {
                  const Element &other = triangles[edge.side[side]];
                  reject_at(triangle.line,
                            "triangles " + std::to_string(other.tag) + " and " +
                              std::to_string(triangle.tag) +
                              " overlap: they lie on the same side of their "
                              "edge between nodes " +
                              std::to_string(nodes[a].tag) + " and " +
                              std::to_string(nodes[b].tag) +
                              " (a repeated or folded triangle, or a surface "
                              "in two physical groups?)");
                }
              edge.side[side] = t;
            }
        }

      // Hanging nodes: a node inside a boundary edge (one triangle only) is
      // a T-junction, and the mesh is not conforming there (a crack the
      // solver would not see). The boundary edges go into a hash grid of
      // cells of the longest one, each node is compared with the edges of
      // its neighbourhood.
      {
        std::vector<std::pair<unsigned int, unsigned int>> boundary_edges;
        double                                             cell_size = 0;
        for (const auto &[key, edge] : edges)
          if (edge.side[0] < 0 || edge.side[1] < 0)
            {
              const unsigned int a = used[key >> 32],
                                 b = used[key & 0xFFFFFFFFULL];
              boundary_edges.emplace_back(a, b);
              cell_size = std::max(cell_size,
                                   std::hypot(nodes[a].x[0] - nodes[b].x[0],
                                              nodes[a].x[1] - nodes[b].x[1]));
            }
        const auto cell_of = [&](const double x, const unsigned int d) {
          return static_cast<long long>(std::floor((x - low[d]) / cell_size));
        };
        const auto key = [](const long long i, const long long j) {
          return static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ULL ^
                 static_cast<std::uint64_t>(j);
        };
        std::unordered_multimap<std::uint64_t, unsigned int> grid;
        for (unsigned int e = 0; cell_size > 0 && e < boundary_edges.size();
             ++e)
          {
            const Node &a = nodes[boundary_edges[e].first],
                       &b = nodes[boundary_edges[e].second];
            for (long long i = cell_of(std::min(a.x[0], b.x[0]), 0);
                 i <= cell_of(std::max(a.x[0], b.x[0]), 0);
                 ++i)
              for (long long j = cell_of(std::min(a.x[1], b.x[1]), 1);
                   j <= cell_of(std::max(a.x[1], b.x[1]), 1);
                   ++j)
                grid.emplace(key(i, j), e);
          }
        for (const unsigned int n : used)
          {
            const Node     &node = nodes[n];
            const long long i    = cell_of(node.x[0], 0),
                            j    = cell_of(node.x[1], 1);
            for (long long di = -1; di <= 1; ++di)
              for (long long dj = -1; dj <= 1; ++dj)
                {
                  const auto range = grid.equal_range(key(i + di, j + dj));
                  for (auto p = range.first; p != range.second; ++p)
                    {
                      const auto [a, b] = boundary_edges[p->second];
                      if (a == n || b == n)
                        continue;
                      const Node  &na = nodes[a], &nb = nodes[b];
                      const double ex      = nb.x[0] - na.x[0],
                                   ey      = nb.x[1] - na.x[1];
                      const double length2 = ex * ex + ey * ey;
                      const double t       = ((node.x[0] - na.x[0]) * ex +
                                        (node.x[1] - na.x[1]) * ey) /
                                       length2;
                      const double distance =
                        std::hypot(na.x[0] + t * ex - node.x[0],
                                   na.x[1] + t * ey - node.x[1]);
                      if (t > 0 && t < 1 && distance <= tolerance)
                        reject_at(node.line,
                                  "node " + std::to_string(node.tag) + " " +
                                    coordinates(node.x) +
                                    " lies on the edge between nodes " +
                                    std::to_string(na.tag) + " and " +
                                    std::to_string(nb.tag) +
                                    " without being a corner of its "
                                    "triangle (a hanging node): the mesh is "
                                    "not conforming there");
                    }
                }
          }
      }

      check_one_body(edges);

      // Line elements: a physical tag is a boundary id, so it must be on a
      // boundary edge (deal.II refuses ids on interior faces, and a line
      // away from the triangles would silently lose its id).
      std::map<std::uint64_t, const Element *> boundary_lines;
      for (const Element &l : lines)
        {
          if (l.physical == 0)
            continue; // no id: nothing to pass on
          const unsigned int a = l.nodes[0], b = l.nodes[1];
          const unsigned int unused = static_cast<unsigned int>(-1);
          const auto         p = (vertex[a] == unused || vertex[b] == unused) ?
                                   edges.end() :
                                   edges.find(edge_key(a, b));
          const std::string  name = "line element " + std::to_string(l.tag) +
                                   " (physical tag " +
                                   std::to_string(l.physical) + ", nodes " +
                                   std::to_string(nodes[a].tag) + " and " +
                                   std::to_string(nodes[b].tag) + ")";
          if (p == edges.end())
            reject_at(l.line,
                      name + " is not an edge of any triangle, so its boundary "
                             "id would be lost");
          if (p->second.side[0] >= 0 && p->second.side[1] >= 0)
            reject_at(l.line,
                      name + " lies inside the mesh, between triangles " +
                        std::to_string(triangles[p->second.side[0]].tag) +
                        " and " +
                        std::to_string(triangles[p->second.side[1]].tag) +
                        ": only boundary edges take a boundary id");
          const auto other = boundary_lines.emplace(p->first, &l);
          if (!other.second)
            {
              if (other.first->second->physical != l.physical)
                reject_at(l.line,
                          name + " and line element " +
                            std::to_string(other.first->second->tag) +
                            " (physical tag " +
                            std::to_string(other.first->second->physical) +
                            ") are the same edge with two boundary ids (a "
                            "curve in two physical groups?)");
              continue;
            }
          CellData<1> face;
          face.vertices    = {vertex[a], vertex[b]};
          face.boundary_id = static_cast<types::boundary_id>(l.physical);
          mesh.boundary.boundary_lines.push_back(face);
        }

      for (const unsigned int n : used)
        mesh.vertices.emplace_back(nodes[n].x[0], nodes[n].x[1]);
      for (const Element &t : triangles)
        {
          CellData<2> cell(3);
          for (unsigned int k = 0; k < 3; ++k)
            cell.vertices[k] = vertex[t.nodes[k]];
          cell.material_id = static_cast<types::material_id>(t.physical);
          mesh.cells.push_back(cell);
        }
      return mesh;
    }



    /// A hash of three vertex indices.
    struct TripleHash
    {
      std::size_t
      operator()(const std::array<unsigned int, 3> &v) const
      {
        return ((static_cast<std::uint64_t>(v[0]) * 0x9E3779B97F4A7C15ULL) ^
                (static_cast<std::uint64_t>(v[1]) * 0xC2B2AE3D27D4EB4FULL) ^
                v[2]);
      }
    };



    GmshMesh<3>
    GmshParser::check_tetrahedra() const
    {
      std::vector<unsigned int> vertex, used;
      std::array<double, 3>     low, high;
      double                    diameter;
      check_nodes(vertex, used, low, high, diameter);
      const double tolerance = distance_tolerance * diameter;
      const auto   node_list = [&](const Element     &element,
                                 const unsigned int n_nodes) {
        std::string text;
        for (unsigned int k = 0; k < n_nodes; ++k)
          text += (k > 0 ? ", " : " ") +
                  std::to_string(nodes[element.nodes[k]].tag) + " " +
                  coordinates(nodes[element.nodes[k]].x, 3);
        return text;
      };

      // Tetrahedra of (nearly) zero volume; the others are oriented as
      // deal.II's reference tetrahedron (positive volume), by swapping two
      // nodes where the file has them the other way round.
      std::vector<std::array<unsigned int, 4>> tetrahedra(cells.size());
      for (unsigned int t = 0; t < cells.size(); ++t)
        {
          const Element &tetrahedron = cells[t];
          // the edges, in units of the diameter, so that nothing overflows
          const auto edge = [&](const unsigned int a, const unsigned int b) {
            Tensor<1, 3> e;
            for (unsigned int d = 0; d < 3; ++d)
              e[d] = (nodes[tetrahedron.nodes[b]].x[d] -
                      nodes[tetrahedron.nodes[a]].x[d]) /
                     diameter;
            return e;
          };
          const double six_volume =
            edge(0, 1) * cross_product_3d(edge(0, 2), edge(0, 3));
          double longest = 0;
          for (unsigned int a = 0; a < 4; ++a)
            for (unsigned int b = a + 1; b < 4; ++b)
              longest = std::max(longest, edge(a, b).norm());
          if (std::abs(six_volume) <= 6 * volume_tolerance ||
              std::abs(six_volume) <=
                distance_tolerance * longest * longest * longest)
            {
              std::ostringstream message;
              const double       volume = std::abs(six_volume) / 6;
              message << "tetrahedron " << tetrahedron.tag;
              if (volume == 0.)
                message << " has zero volume";
              else
                message << " has nearly zero volume "
                        << volume * diameter * diameter * diameter;
              message << ": its nodes" << node_list(tetrahedron, 4) << " are "
                      << (volume == 0. ? "" : "nearly ") << "coplanar";
              reject_at(tetrahedron.line, message.str());
            }
          for (unsigned int k = 0; k < 4; ++k)
            tetrahedra[t][k] = vertex[tetrahedron.nodes[k]];
          if (six_volume < 0)
            std::swap(tetrahedra[t][1], tetrahedra[t][2]);
        }

      // Each face borders at most two tetrahedra, one on each side:
      // otherwise they overlap. The side is the parity of the permutation
      // that sorts the face's vertices in its outward order.
      struct FaceCells
      {
        // tetrahedron (index) on each side, -1 if none
        std::array<int, 2> side = {{-1, -1}};
      };
      std::unordered_map<std::array<unsigned int, 3>, FaceCells, TripleHash>
        faces_of_cells;
      faces_of_cells.reserve(2 * cells.size() + 16);
      // the faces of a positively oriented tetrahedron, normals outward
      const unsigned int outward[4][3] = {{1, 2, 3},
                                          {0, 3, 2},
                                          {0, 1, 3},
                                          {0, 2, 1}};
      for (unsigned int t = 0; t < cells.size(); ++t)
        for (const auto &f : outward)
          {
            std::array<unsigned int, 3> v = {
              {tetrahedra[t][f[0]], tetrahedra[t][f[1]], tetrahedra[t][f[2]]}};
            unsigned int swaps = 0;
            for (unsigned int i = 0; i < 2; ++i)
              for (unsigned int j = 0; j + 1 < 3 - i; ++j)
                if (v[j] > v[j + 1])
                  {
                    std::swap(v[j], v[j + 1]);
                    ++swaps;
                  }
            const unsigned int side = swaps % 2;
            FaceCells         &face = faces_of_cells[v];
            if (face.side[side] >= 0)
              reject_at(cells[t].line,
                        "tetrahedra " +
                          std::to_string(cells[face.side[side]].tag) + " and " +
                          std::to_string(cells[t].tag) +
                          " overlap: they lie on the same side of their face "
                          "between nodes " +
                          std::to_string(nodes[used[v[0]]].tag) + ", " +
                          std::to_string(nodes[used[v[1]]].tag) + " and " +
                          std::to_string(nodes[used[v[2]]].tag) +
                          " (a repeated or folded tetrahedron, or a volume "
                          "in two physical groups?)");
            face.side[side] = t;
          }

      // Hanging nodes: a node on a boundary face (one tetrahedron only)
      // without being one of its corners makes the mesh non-conforming (a
      // crack the solver would not see). The boundary faces go into hash
      // grids, one per size class (cells of 2^l times the shortest face
      // size, a face in the class of its longest edge: a graded mesh puts
      // few faces into any cell), and each node is compared with the faces
      // of its neighbourhood in every class.
      {
        const auto point = [&](const unsigned int v) {
          const auto &x = nodes[used[v]].x;
          return Point<3>(x[0], x[1], x[2]);
        };
        std::vector<std::array<unsigned int, 3>> boundary_faces;
        std::vector<double>                      face_size;
        for (const auto &[key, face] : faces_of_cells)
          if (face.side[0] < 0 || face.side[1] < 0)
            {
              double longest = 0;
              for (unsigned int k = 0; k < 3; ++k)
                longest =
                  std::max(longest,
                           point(key[k]).distance(point(key[(k + 1) % 3])));
              boundary_faces.push_back(key);
              face_size.push_back(longest);
            }
        const double smallest =
          *std::min_element(face_size.begin(), face_size.end());
        const auto cell_of =
          [&](const double x, const unsigned int d, const double cell_size) {
            return static_cast<long long>(std::floor((x - low[d]) / cell_size));
          };
        const auto key = [](const int       level,
                            const long long i,
                            const long long j,
                            const long long k) {
          return ((static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ULL ^
                   static_cast<std::uint64_t>(j)) *
                    0xC2B2AE3D27D4EB4FULL ^
                  static_cast<std::uint64_t>(k)) *
                   0x165667B19E3779F9ULL ^
                 static_cast<std::uint64_t>(level);
        };
        std::unordered_multimap<std::uint64_t, unsigned int> grid;
        int                                                  n_levels = 0;
        for (unsigned int f = 0; f < boundary_faces.size(); ++f)
          {
            const int level =
              std::max(0,
                       static_cast<int>(std::ceil(
                         std::log2(face_size[f] / smallest) - 1e-12)));
            n_levels               = std::max(n_levels, level + 1);
            const double cell_size = smallest * std::ldexp(1., level);
            std::array<long long, 3> first, last;
            for (unsigned int d = 0; d < 3; ++d)
              {
                double a = point(boundary_faces[f][0])[d], b = a;
                for (unsigned int k = 1; k < 3; ++k)
                  {
                    a = std::min(a, point(boundary_faces[f][k])[d]);
                    b = std::max(b, point(boundary_faces[f][k])[d]);
                  }
                first[d] = cell_of(a, d, cell_size);
                last[d]  = cell_of(b, d, cell_size);
              }
            for (long long i = first[0]; i <= last[0]; ++i)
              for (long long j = first[1]; j <= last[1]; ++j)
                for (long long k = first[2]; k <= last[2]; ++k)
                  grid.emplace(key(level, i, j, k), f);
          }
        for (unsigned int v = 0; v < used.size(); ++v)
          for (int level = 0; level < n_levels; ++level)
            {
              const double    cell_size = smallest * std::ldexp(1., level);
              const Point<3>  p         = point(v);
              const long long i         = cell_of(p[0], 0, cell_size),
                              j         = cell_of(p[1], 1, cell_size),
                              k         = cell_of(p[2], 2, cell_size);
              for (long long di = -1; di <= 1; ++di)
                for (long long dj = -1; dj <= 1; ++dj)
                  for (long long dk = -1; dk <= 1; ++dk)
                    {
                      const auto range =
                        grid.equal_range(key(level, i + di, j + dj, k + dk));
                      for (auto q = range.first; q != range.second; ++q)
                        {
                          const auto &face = boundary_faces[q->second];
                          if (face[0] == v || face[1] == v || face[2] == v)
                            continue;
                          const Point<3>     a      = point(face[0]);
                          const Tensor<1, 3> ab     = point(face[1]) - a,
                                             ac     = point(face[2]) - a,
                                             ap     = p - a;
                          const Tensor<1, 3> normal = cross_product_3d(ab, ac);
                          const double       n2     = normal.norm_square();
                          // barycentric coordinates of p's projection
                          const double l1 =
                                         cross_product_3d(ap, ac) * normal / n2,
                                       l2 =
                                         cross_product_3d(ab, ap) * normal / n2;
                          const double distance =
                            std::abs(ap * normal) / std::sqrt(n2);
                          if (distance <= tolerance &&
                              l1 >= -distance_tolerance &&
                              l2 >= -distance_tolerance &&
                              l1 + l2 <= 1 + distance_tolerance)
                            reject_at(
                              nodes[used[v]].line,
                              "node " + std::to_string(nodes[used[v]].tag) +
                                " " + coordinates(nodes[used[v]].x, 3) +
                                " lies on the boundary face between nodes " +
                                std::to_string(nodes[used[face[0]]].tag) +
                                ", " +
                                std::to_string(nodes[used[face[1]]].tag) +
                                " and " +
                                std::to_string(nodes[used[face[2]]].tag) +
                                " without being a corner of its tetrahedron "
                                "(a hanging node): the mesh is not "
                                "conforming there");
                        }
                    }
            }
      }

      check_one_body(faces_of_cells);

      // Triangle elements: a physical tag is a boundary id, so it must be
      // on a boundary face (deal.II refuses ids on interior faces, and a
      // triangle away from the tetrahedra would silently lose its id).
      GmshMesh<3>                                            mesh;
      std::map<std::array<unsigned int, 3>, const Element *> tagged_faces;
      const unsigned int unused = static_cast<unsigned int>(-1);
      for (const Element &triangle : faces)
        {
          if (triangle.physical == 0)
            continue; // no id: nothing to pass on
          std::array<unsigned int, 3> v;
          for (unsigned int k = 0; k < 3; ++k)
            v[k] = vertex[triangle.nodes[k]];
          std::sort(v.begin(), v.end());
          const auto p =
            v[2] == unused ? faces_of_cells.end() : faces_of_cells.find(v);
          const std::string name =
            "triangle element " + std::to_string(triangle.tag) +
            " (physical tag " + std::to_string(triangle.physical) + ", nodes" +
            node_list(triangle, 3) + ")";
          if (p == faces_of_cells.end())
            reject_at(triangle.line,
                      name + " is not a face of any tetrahedron, so its "
                             "boundary id would be lost");
          if (p->second.side[0] >= 0 && p->second.side[1] >= 0)
            reject_at(triangle.line,
                      name + " lies inside the mesh, between tetrahedra " +
                        std::to_string(cells[p->second.side[0]].tag) + " and " +
                        std::to_string(cells[p->second.side[1]].tag) +
                        ": only boundary faces take a boundary id");
          const auto other = tagged_faces.emplace(v, &triangle);
          if (!other.second)
            {
              if (other.first->second->physical != triangle.physical)
                reject_at(triangle.line,
                          name + " and triangle element " +
                            std::to_string(other.first->second->tag) +
                            " (physical tag " +
                            std::to_string(other.first->second->physical) +
                            ") are the same face with two boundary ids (a "
                            "surface in two physical groups?)");
              continue;
            }
          CellData<2> face(3);
          for (unsigned int k = 0; k < 3; ++k)
            face.vertices[k] = vertex[triangle.nodes[k]];
          face.boundary_id = static_cast<types::boundary_id>(triangle.physical);
          mesh.boundary.boundary_quads.push_back(face);
        }

      for (const unsigned int n : used)
        mesh.vertices.emplace_back(nodes[n].x[0], nodes[n].x[1], nodes[n].x[2]);
      for (unsigned int t = 0; t < cells.size(); ++t)
        {
          CellData<3> cell(4);
          for (unsigned int k = 0; k < 4; ++k)
            cell.vertices[k] = tetrahedra[t][k];
          cell.material_id = static_cast<types::material_id>(cells[t].physical);
          mesh.cells.push_back(cell);
        }
      return mesh;
    }
  } // namespace



  template <int dim>
  GmshMesh<dim>
  read_gmsh_file(const std::string &path)
  {
    std::error_code                    error;
    const std::filesystem::file_status status =
      std::filesystem::status(path, error);
    if (std::filesystem::is_directory(status))
      throw InputError("cannot open mesh file <" + path +
                       ">: it is a directory");
    // a device or a pipe could block or never end (/dev/zero)
    if (std::filesystem::exists(status) &&
        !std::filesystem::is_regular_file(status))
      throw InputError("cannot open mesh file <" + path +
                       ">: it is not a regular file");
    std::ifstream in(path, std::ios::binary);
    if (!in)
      throw InputError("cannot open mesh file <" + path + ">");
    const std::string text((std::istreambuf_iterator<char>(in)),
                           std::istreambuf_iterator<char>());
    if (in.bad())
      throw InputError("cannot read mesh file <" + path + ">");
    return read_gmsh_text<dim>(path, text);
  }



  template <int dim>
  GmshMesh<dim>
  read_gmsh_text(const std::string &name, const std::string &text)
  {
    // a UTF-8 byte order mark, which some editors write, is not content
    const std::string bom = "\xEF\xBB\xBF";
    const std::string content =
      text.compare(0, 3, bom) == 0 ? text.substr(3) : text;
    GmshParser parser(name, content, dim);
    parser.parse();
    if constexpr (dim == 2)
      return parser.check_triangles();
    else
      return parser.check_tetrahedra();
  }

  template GmshMesh<2>
  read_gmsh_file<2>(const std::string &path);
  template GmshMesh<3>
  read_gmsh_file<3>(const std::string &path);
  template GmshMesh<2>
  read_gmsh_text<2>(const std::string &name, const std::string &text);
  template GmshMesh<3>
  read_gmsh_text<3>(const std::string &name, const std::string &text);
} // namespace Signorini
