#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>

#include <signorini/input_error.h>
#include <signorini/linear_solver.h>
#include <signorini/registry.h>

#include <Amesos.h>
#include <Amesos_BaseSolver.h>
#include <Epetra_LinearProblem.h>
#include <algorithm>

namespace Signorini
{
  namespace
  {
    using Lines = AffineConstraints<double>::LineRange;

    /**
     * The constraint lines as a rank needs them: those of its own dofs, and
     * the dofs that lines with entries couple (the few active contact rows
     * of the integral condition, hanging nodes), whose values are imported
     * when there are any.
     */
    struct DistributedLines
    {
      DistributedLines(const Lines lines, const IndexSet &owned)
      {
        coupled.set_size(owned.size());
        for (const auto &line : lines)
          {
            if (owned.is_element(line.index))
              own.push_back(&line);
            if (!line.entries.empty())
              {
                coupled.add_index(line.index);
                for (const auto &entry : line.entries)
                  coupled.add_index(entry.first);
              }
          }
        coupled.compress();
        for (const auto *line : own)
          if (!line->entries.empty())
            own_with_entries.push_back(line);
      }

      /// v_j += w v_i for the lines x_i = sum_j w x_j of this rank (the
      /// transpose of the constraints; the masters j may belong to other
      /// ranks: add, then exchange)
      void
      add_to_masters(LA::Vector &v) const
      {
        if (coupled.is_empty())
          return;
        std::vector<types::global_dof_index> indices;
        std::vector<double>                  values;
        for (const auto *line : own_with_entries)
          for (const auto &[j, w] : line->entries)
            {
              indices.push_back(j);
              values.push_back(w * v[line->index]);
            }
        v.add(indices, values);
        v.compress(VectorOperation::add);
      }

      using Line = AffineConstraints<double>::ConstraintLine;
      std::vector<const Line *> own;
      std::vector<const Line *> own_with_entries;
      IndexSet                  coupled; // the same on every rank
    };

    /// C^T K C + Id_c: K acting on the dofs the constraints leave free.
    class ConstrainedOperator
    {
    public:
      ConstrainedOperator(const LA::SparseMatrix          &matrix,
                          const DistributedLines          &lines,
                          const LA::Vector                &layout,
                          const ElasticitySolver::Springs &springs)
        : matrix(matrix)
        , lines(lines)
      {
        // (the springs of the rows this rank owns, and the columns they
        // read, which may belong to other ranks: the integral condition's
        // springs couple neighbouring nodes)
        const IndexSet owned = layout.locally_owned_elements();
        with_springs         = !springs.empty(); // the same on every rank
        IndexSet spring_columns(owned.size());
        for (const auto &spring : springs)
          if (owned.is_element(std::get<0>(spring)))
            {
              own_springs.push_back(spring);
              spring_columns.add_index(std::get<1>(spring));
            }
        if (with_springs)
          spring_ghosted = with_ghosts(layout, spring_columns);
        if (!lines.coupled.is_empty())
          ghosted = with_ghosts(layout, lines.coupled);
      }

      /// dst += S x, S the springs (a collective: every rank adds and
      /// exchanges, also those without springs)
      void
      add_springs(LA::Vector &dst, const LA::Vector &x) const
      {
        // (an element-wise += followed by insertions made Trilinos
        // exchange on the ranks that own springs only, and the others
        // waited in another collective)
        if (!with_springs)
          return;
        spring_ghosted = x;
        std::vector<types::global_dof_index> indices;
        std::vector<double>                  values;
        for (const auto &[i, j, value] : own_springs)
          {
            indices.push_back(i);
            values.push_back(value * spring_ghosted[j]);
          }
        dst.add(indices, values);
        dst.compress(VectorOperation::add);
      }

      void
      vmult(LA::Vector &dst, const LA::Vector &src) const
      {
        if (!lines.coupled.is_empty())
          ghosted = src; // import the coupled entries
        distributed.reinit(src, /*omit_zeroing_entries=*/true);
        distributed = src;
        for (const auto *line : lines.own)
          {
            double value = 0.;
            for (const auto &[j, w] : line->entries)
              value += w * ghosted[j];
            distributed[line->index] = value;
          }
        distributed.compress(VectorOperation::insert);
        matrix.vmult(dst, distributed);
        // (on C src, like K: a spring may reach a constrained dof)
        add_springs(dst, distributed);
        lines.add_to_masters(dst);
        for (const auto *line : lines.own)
          dst[line->index] = src[line->index];
        dst.compress(VectorOperation::insert);
      }

    private:
      const LA::SparseMatrix   &matrix;
      const DistributedLines   &lines;
      ElasticitySolver::Springs own_springs;
      bool                      with_springs;
      mutable LA::Vector        distributed;
      mutable LA::Vector        ghosted;
      mutable LA::Vector        spring_ghosted;
    };

    /// Id_c + (P^{-1} restricted to the free dofs), P = K with the
    /// constrained dofs eliminated.
    template <typename Inner>
    class ConstrainedPreconditioner
    {
    public:
      ConstrainedPreconditioner(const Inner            &inner,
                                const DistributedLines &lines)
        : inner(inner)
        , lines(lines)
      {}

      void
      vmult(LA::Vector &dst, const LA::Vector &src) const
      {
        restricted.reinit(src, true);
        restricted = src;
        for (const auto *line : lines.own)
          restricted[line->index] = 0.;
        restricted.compress(VectorOperation::insert);
        inner(dst, restricted);
        for (const auto *line : lines.own)
          dst[line->index] = src[line->index];
        dst.compress(VectorOperation::insert);
      }

    private:
      const Inner            &inner;
      const DistributedLines &lines;
      mutable LA::Vector      restricted;
    };
  } // namespace



  namespace
  {
    /// The names of the types in Linear solver/Type.
    const NamedValues<ElasticitySolver::Type> &
    type_names()
    {
      using Type = ElasticitySolver::Type;
      static const NamedValues<Type> names(
        {{"automatic",
          Type::automatic,
          "chosen by the number of DoFs, see 'Direct solver limit'"},
         {"direct", Type::direct, "sparse direct factorisation"},
         {"AMG-CG", Type::amg_cg, "Trilinos ML AMG"}});
      return names;
    }

    /// The direct packages this Trilinos was built with.
    std::vector<std::string>
    available_direct_packages()
    {
      Amesos                   factory;
      std::vector<std::string> available;
      for (const std::string name :
           {"Amesos_Klu", "Amesos_Umfpack", "Amesos_Mumps", "Amesos_Lapack"})
        if (factory.Query(name))
          available.push_back(name);
      return available;
    }
  } // namespace



  void
  ElasticitySolver::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Linear solver");
    {
      prm.declare_entry("Type",
                        type_names().default_name(),
                        Patterns::Selection(type_names().selection()),
                        type_names().help("Preconditioner of the CG solves"));
      prm.declare_entry("Direct solver limit",
                        "10000",
                        Patterns::Integer(0),
                        "With Type = automatic: largest number of DoFs for "
                        "which the direct factorisation is used.");
      prm.declare_entry(
        "Direct solver package",
        "automatic",
        Patterns::Selection(
          "automatic|Amesos_Klu|Amesos_Umfpack|Amesos_Mumps|Amesos_Lapack"),
        "Trilinos Amesos package of the direct factorisation; automatic: "
        "Amesos_Klu for triangles, Amesos_Mumps for tetrahedra, on which "
        "KLU's factors fill in (5 times slower at 6 000 DoFs, 40 times at "
        "22 000: bench/small_runs), Amesos_Klu if Trilinos lacks MUMPS.");
      prm.declare_entry("Relative tolerance",
                        "1e-10",
                        Patterns::Double(1e-16, 1e-2),
                        "CG stops when the residual is below this fraction of "
                        "the right-hand side.");
      prm.enter_subsection("AMG");
      {
        prm.declare_entry("Null space",
                          "rigid motions",
                          Patterns::Selection("rigid motions|translations"),
                          "Near null space of the aggregates: the rigid "
                          "motions (translations and rotations) or the "
                          "translations only.");
        prm.declare_entry("Aggregation threshold",
                          "0",
                          Patterns::Double(0., 1.),
                          "Matrix entries below this fraction of the "
                          "diagonal are dropped when aggregating (ML's "
                          "aggregation: threshold).");
        prm.declare_entry("Smoother sweeps",
                          "1",
                          Patterns::Integer(1, 10),
                          "Chebyshev smoother sweeps before and after each "
                          "coarse correction.");
        prm.declare_entry("W-cycle",
                          "true",
                          Patterns::Bool(),
                          "W-cycles (true) or V-cycles (false).");
        prm.declare_entry("Smoothed aggregation",
                          "true",
                          Patterns::Bool(),
                          "Smooth the tentative prolongators (true: fewer CG "
                          "iterations) or not (false: much less memory, more "
                          "CG iterations; see doc/benchmarks.md, Memory).");
        prm.declare_entry("Low memory",
                          "false",
                          Patterns::Bool(),
                          "Build the hierarchy by plain aggregation from K "
                          "itself, with no copy of K (the least memory, for "
                          "the largest meshes; 'Smoothed aggregation' is not "
                          "used; see doc/benchmarks.md, Memory).");
      }
      prm.leave_subsection();
      prm.declare_entry("Maximum iterations",
                        "5000",
                        Patterns::Integer(1),
                        "CG iteration limit per solve.");
    }
    prm.leave_subsection();
  }



  void
  ElasticitySolver::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Linear solver");
    {
      type                = type_names().value(prm.get("Type"));
      direct_solver_limit = prm.get_integer("Direct solver limit");
      direct_package      = prm.get("Direct solver package");
      relative_tolerance  = prm.get_double("Relative tolerance");
      max_iterations      = prm.get_integer("Maximum iterations");
      prm.enter_subsection("AMG");
      with_rotations        = prm.get("Null space") == "rigid motions";
      aggregation_threshold = prm.get_double("Aggregation threshold");
      smoother_sweeps       = prm.get_integer("Smoother sweeps");
      w_cycle               = prm.get_bool("W-cycle");
      smoothed_aggregation  = prm.get_bool("Smoothed aggregation");
      low_memory            = prm.get_bool("Low memory");
      prm.leave_subsection();
    }
    prm.leave_subsection();
    // the Selection names every package Amesos knows; which of them this
    // Trilinos was built with is known only to its factory (as for
    // deal.II's SolverDirect), so that --validate refuses what a run would
    if (direct_package == "automatic")
      return;
    const std::vector<std::string> available = available_direct_packages();
    if (std::find(available.begin(), available.end(), direct_package) ==
        available.end())
      {
        std::string list;
        for (const auto &name : available)
          list += (list.empty() ? "" : ", ") + name;
        throw InputError(
          "Linear solver/Direct solver package = " + direct_package +
          ": not available in this Trilinos build (available: " +
          (list.empty() ? std::string("none") : list) + ")");
      }
  }



  ElasticitySolver::ElasticitySolver() = default;



  ElasticitySolver::~ElasticitySolver() = default;



  void
  ElasticitySolver::initialize(
    const LA::SparseMatrix                     &stiffness,
    const AffineConstraints<double>            &base_constraints,
    const std::vector<std::vector<bool>>       &constant_modes,
    const std::vector<LA::Vector>              &motions,
    const std::vector<types::global_dof_index> &supports,
    const bool                                  prefer_direct)
  {
    rigid_motions     = &motions;
    stiffness_matrix  = &stiffness;
    translation_modes = constant_modes;
    // (the translation modes are one per component: their number is the
    // dimension; a rank without dofs has none, and every rank must give the
    // AMG the same number and choose the same direct package)
    const unsigned int dimension =
      Utilities::MPI::max(static_cast<unsigned int>(constant_modes.size()),
                          stiffness.get_mpi_communicator());
    translation_modes.resize(dimension);
    base_eliminated_dofs = supports;
    for (const auto &line : base_constraints.get_lines())
      base_eliminated_dofs.push_back(line.index);
    std::sort(base_eliminated_dofs.begin(), base_eliminated_dofs.end());
    base_eliminated_dofs.erase(std::unique(base_eliminated_dofs.begin(),
                                           base_eliminated_dofs.end()),
                               base_eliminated_dofs.end());
    package = direct_package;
    if (direct_package == "automatic")
      {
        const std::vector<std::string> available = available_direct_packages();
        package =
          (dimension == 3 &&
           std::find(available.begin(), available.end(), "Amesos_Mumps") !=
             available.end()) ?
            "Amesos_Mumps" :
            "Amesos_Klu";
      }
    use_direct = (type == Type::direct) ||
                 (type == Type::automatic &&
                  (stiffness.m() <= direct_solver_limit || prefer_direct));
    release_preconditioner();
  }



  void
  ElasticitySolver::release_preconditioner()
  {
    direct.reset();
    direct_problem.reset();
    analysed_matrix = nullptr;
    amg.reset();
    aggregation_amg.reset();
    null_space.reset();
    modified_matrix.clear();
    current_eliminated_dofs = {numbers::invalid_dof_index}; // (none built)
  }



  void
  ElasticitySolver::update_preconditioner(
    const std::vector<types::global_dof_index> &active_dofs,
    const ElasticitySolver::Springs            &springs)
  {
    Assert(stiffness_matrix != nullptr, ExcNotInitialized());
    std::vector<types::global_dof_index> eliminated_dofs(active_dofs);
    std::sort(eliminated_dofs.begin(), eliminated_dofs.end());
    if (eliminated_dofs == current_eliminated_dofs && springs.empty() &&
        !preconditioned_springs)
      return;
    preconditioned_springs = !springs.empty();
    // zero the rows and columns of the eliminated dofs in the rows this rank
    // owns (the lists are the same on every rank); the matrix is copied again
    // each time, so that restored rows get their entries back
    std::vector<bool> eliminated(stiffness_matrix->n(), false);
    for (const auto dof : base_eliminated_dofs)
      eliminated[dof] = true;
    for (const auto dof : eliminated_dofs)
      eliminated[dof] = true;
    if (!use_direct && low_memory)
      {
        // (masks the eliminated dofs of K itself: no copy; the former
        // hierarchy is freed before the new one is built)
        aggregation_amg.reset();
        AggregationMultigrid::AdditionalData data;
        data.smoother_degree = smoother_sweeps;
        data.w_cycle         = w_cycle;
        Assert(rigid_motions != nullptr &&
                 rigid_motions->size() >= translation_modes.size(),
               ExcInternalError());
        aggregation_amg = std::make_unique<AggregationMultigrid>();
        aggregation_amg->initialize(*stiffness_matrix,
                                    eliminated,
                                    translation_modes.size(),
                                    *rigid_motions,
                                    with_rotations ? rigid_motions->size() :
                                                     translation_modes.size(),
                                    data);
        current_eliminated_dofs = eliminated_dofs;
        return;
      }
    modified_matrix.copy_from(*stiffness_matrix);
    // (Epetra's row views: deal.II's row iterators copy each row)
    const Epetra_CrsMatrix &source = stiffness_matrix->trilinos_matrix();
    std::vector<types::global_dof_index> columns;
    std::vector<double>                  zeros;
    for (int local_row = 0; local_row < source.NumMyRows(); ++local_row)
      {
        const types::global_dof_index row = source.GRID(local_row);
        int                           n_entries;
        double                       *values;
        int                          *local_columns;
        source.ExtractMyRowView(local_row, n_entries, values, local_columns);
        columns.clear();
        for (int k = 0; k < n_entries; ++k)
          {
            const types::global_dof_index column =
              source.ColMap().GID(local_columns[k]);
            if (column != row && (eliminated[row] || eliminated[column]))
              columns.push_back(column);
          }
        zeros.assign(columns.size(), 0.);
        if (!columns.empty())
          modified_matrix.set(row, columns, zeros);
      }
    modified_matrix.compress(VectorOperation::insert);
    {
      const IndexSet owned = modified_matrix.locally_owned_range_indices();
      for (const auto &[row, column, value] : springs)
        if (owned.is_element(row) && !eliminated[row] && !eliminated[column])
          modified_matrix.add(row, column, value);
      modified_matrix.compress(VectorOperation::add);
    }
    build_preconditioner(modified_matrix);
    current_eliminated_dofs = eliminated_dofs; // (once built)
  }



  void
  ElasticitySolver::build_preconditioner(const LA::SparseMatrix &matrix)
  {
    amg.reset();
    if (use_direct)
      {
        const Epetra_CrsMatrix &epetra_matrix = matrix.trilinos_matrix();
        int                     status        = 0;
        if (!direct || analysed_matrix != &epetra_matrix)
          {
            direct.reset();
            direct_problem = std::make_unique<Epetra_LinearProblem>();
            // (Amesos reads the operator, it does not change it)
            direct_problem->SetOperator(
              const_cast<Epetra_CrsMatrix *>(&epetra_matrix));
            Amesos factory;
            direct.reset(factory.Create(package, *direct_problem));
            if (!direct)
              throw InputError(
                "Linear solver/Direct solver package = " + package +
                ": not available in this Trilinos build");
            status          = direct->SymbolicFactorization();
            analysed_matrix = &epetra_matrix;
          }
        if (status == 0)
          status = direct->NumericFactorization();
        if (status != 0)
          {
            direct.reset();
            analysed_matrix = nullptr;
            throw InputError("Linear solver/Direct solver package = " +
                             package + ": the factorisation failed (Amesos " +
                             "error " + std::to_string(status) + ")");
          }
      }
    else
      {
        direct.reset();
        direct_problem.reset();
        analysed_matrix = nullptr;
        TrilinosWrappers::PreconditionAMG::AdditionalData data;
        data.elliptic              = true;
        data.higher_order_elements = false;
        data.smoother_sweeps       = smoother_sweeps;
        data.aggregation_threshold = aggregation_threshold;
        data.w_cycle               = w_cycle;
        data.constant_modes        = translation_modes;
        amg = std::make_unique<TrilinosWrappers::PreconditionAMG>();
        // deal.II's parameter list, with what deal.II 9.4 does not set: ML
        // aggregates best when its near null space holds the rotations too
        // (deal.II passes the translations only), and it must be told that
        // the dofs come in consecutive groups, one per vertex (deal.II's
        // numbering of the vector P1 element, never renumbered here), to
        // aggregate vertices rather than single dofs
        Teuchos::ParameterList parameters;
        data.set_parameters(parameters, null_space, matrix);
        parameters.set("PDE equations",
                       static_cast<int>(translation_modes.size()));
        if (!smoothed_aggregation)
          parameters.set("aggregation: damping factor", 0.);
        if (with_rotations && rigid_motions != nullptr &&
            !rigid_motions->empty())
          {
            const Epetra_Map &map =
              matrix.trilinos_matrix().OperatorDomainMap();
            null_space =
              std::make_unique<Epetra_MultiVector>(map, rigid_motions->size());
            for (unsigned int m = 0; m < rigid_motions->size(); ++m)
              for (int i = 0; i < map.NumMyElements(); ++i)
                (*null_space)[m][i] =
                  (*rigid_motions)[m][static_cast<types::global_dof_index>(
                    map.GID(i))];
            parameters.set("null space: type", "pre-computed");
            parameters.set("null space: dimension", null_space->NumVectors());
            parameters.set("null space: vectors", null_space->Values());
          }
        amg->initialize(matrix, parameters);
      }
  }



  unsigned int
  ElasticitySolver::solve(const AffineConstraints<double> &constraints,
                          const LA::Vector                &load,
                          LA::Vector                      &solution,
                          const double                     tolerance_,
                          const Springs                   &springs)
  {
    if (stiffness_matrix == nullptr)
      throw std::logic_error(
        "ElasticitySolver::solve(): call initialize() first");
    if (!direct && !amg && !aggregation_amg)
      update_preconditioner({});
    const DistributedLines    lines(constraints.get_lines(),
                                 load.locally_owned_elements());
    const ConstrainedOperator op(*stiffness_matrix, lines, load, springs);
    // right-hand side C^T (f - (K + S) k) + Id_c k
    LA::Vector rhs(load);
    {
      LA::Vector inhomogeneity(load); // (freed before CG allocates)
      inhomogeneity = 0.;
      for (const auto *line : lines.own)
        inhomogeneity[line->index] = line->inhomogeneity;
      inhomogeneity.compress(VectorOperation::insert);
      stiffness_matrix->vmult(rhs, inhomogeneity);
      op.add_springs(rhs, inhomogeneity);
    }
    rhs.sadd(-1., 1., load);
    lines.add_to_masters(rhs);
    for (const auto *line : lines.own)
      rhs[line->index] = line->inhomogeneity;
    rhs.compress(VectorOperation::insert);
    for (const auto *line : lines.own)
      solution[line->index] = line->inhomogeneity;
    solution.compress(VectorOperation::insert);

    // the tolerance relative to the forces of the free rows: the
    // constrained rows hold displacements (and start with a zero
    // residual), which would make it loose for a small E or tight for a
    // large one
    double force_norm = 0.;
    {
      LA::Vector forces(rhs);
      for (const auto *line : lines.own)
        forces[line->index] = 0.;
      forces.compress(VectorOperation::insert);
      force_norm = forces.l2_norm();
    }
    const double  tol = (tolerance_ > 0. ? tolerance_ : relative_tolerance);
    SolverControl control(max_iterations, tol * force_norm, false, false);
    SolverCG<LA::Vector> cg(control);
    try
      {
        // the preconditioner built: direct, ML or the low-memory hierarchy
        const auto inner = [this](LA::Vector &dst, const LA::Vector &src) {
          if (direct)
            {
              direct_problem->SetLHS(&dst.trilinos_vector());
              direct_problem->SetRHS(
                const_cast<Epetra_MultiVector *>(&src.trilinos_vector()));
              if (direct->Solve() != 0)
                throw std::runtime_error("the direct solve (" + package +
                                         ") failed");
            }
          else if (aggregation_amg)
            aggregation_amg->vmult(dst, src);
          else
            amg->vmult(dst, src);
        };
        const ConstrainedPreconditioner<decltype(inner)> preconditioner(inner,
                                                                        lines);
        cg.solve(op, solution, rhs, preconditioner);
      }
    catch (const SolverControl::NoConvergence &exc)
      {
        throw std::runtime_error(
          "the linear elasticity solve did not converge in " +
          std::to_string(exc.last_step) + " CG iterations (residual " +
          Utilities::to_string(exc.last_residual) +
          "; Linear solver/Maximum iterations and Relative tolerance)");
      }
    constraints.distribute(solution);
    return control.last_step();
  }



  bool
  ElasticitySolver::uses_direct_solver() const
  {
    return use_direct;
  }



  std::string
  ElasticitySolver::method() const
  {
    return use_direct ? type_names().name(Type::direct) + " (" + package + ")" :
                        type_names().name(Type::amg_cg);
  }
} // namespace Signorini
