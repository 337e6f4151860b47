#ifndef signorini_registry_h
#define signorini_registry_h

#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>

#include <signorini/input_error.h>

#include <algorithm>
#include <functional>
#include <memory>
#include <string>
#include <tuple>
#include <type_traits>
#include <typeindex>
#include <typeinfo>
#include <utility>
#include <vector>

namespace Signorini
{
  using namespace dealii;

  namespace internal
  {
    /// Whether @p T has static declare_parameters(ParameterHandler &) and
    /// parse_parameters(ParameterHandler &).
    template <typename T, typename = void>
    struct HasParameters : std::false_type
    {};

    template <typename T>
    struct HasParameters<
      T,
      std::void_t<decltype(T::declare_parameters(
                    std::declval<ParameterHandler &>())),
                  decltype(std::declval<T &>().parse_parameters(
                    std::declval<ParameterHandler &>()))>> : std::true_type
    {};

    /// T::is_implemented where T declares it, true otherwise.
    template <typename T, typename = void>
    struct IsImplemented : std::true_type
    {};

    template <typename T>
    struct IsImplemented<T, std::void_t<decltype(T::is_implemented)>>
      : std::bool_constant<T::is_implemented>
    {};

    /// "'a' (x), 'b' (y) or 'c' (z)": the choices of a help string.
    inline std::string
    list_of_choices(
      const std::vector<std::pair<std::string, std::string>> &choices)
    {
      std::string text;
      for (unsigned int i = 0; i < choices.size(); ++i)
        {
          if (i > 0)
            text += (i + 1 == choices.size()) ? " or " : ", ";
          text += "'" + choices[i].first + "'";
          if (!choices[i].second.empty())
            text += " (" + choices[i].second + ")";
        }
      return text;
    }
  } // namespace internal



  /**
   * The names of the values of an enumeration chosen by a Patterns::Selection
   * entry, each written once: the pattern, the parsing of the entry and the
   * name of a value all come from this table, so that the value is parsed
   * once and compared as an enumerator afterwards.
   */
  template <typename T>
  class NamedValues
  {
  public:
    /// (name, value, description) in the order of the selection; the first
    /// is the default.
    explicit NamedValues(
      std::vector<std::tuple<std::string, T, std::string>> entries)
      : entries(std::move(entries))
    {}

    /// "a|b|c" for Patterns::Selection.
    std::string
    selection() const
    {
      std::string text;
      for (const auto &entry : entries)
        text += (text.empty() ? "" : "|") + std::get<0>(entry);
      return text;
    }

    /// The first name: the default of the entry.
    const std::string &
    default_name() const
    {
      return std::get<0>(entries.front());
    }

    /// "@p help: 'a' (description), 'b' (...) or 'c' (...)."
    std::string
    help(const std::string &help) const
    {
      std::vector<std::pair<std::string, std::string>> choices;
      for (const auto &entry : entries)
        choices.emplace_back(std::get<0>(entry), std::get<2>(entry));
      return help + ": " + internal::list_of_choices(choices) + ".";
    }

    /// The value named @p name; throws InputError for an unknown name.
    T
    value(const std::string &name) const
    {
      for (const auto &entry : entries)
        if (std::get<0>(entry) == name)
          return std::get<1>(entry);
      throw InputError("unknown choice <" + name + ">, expected one of " +
                       selection());
    }

    /// The name of @p value.
    const std::string &
    name(const T value) const
    {
      for (const auto &entry : entries)
        if (std::get<1>(entry) == value)
          return std::get<0>(entry);
      AssertThrow(false, ExcMessage("value without a name"));
      return std::get<0>(entries.front());
    }

  private:
    /// (name, value, description)
    std::vector<std::tuple<std::string, T, std::string>> entries;
  };



  /**
   * The members of a family of interchangeable parts (contact conditions,
   * contact solvers, stress reconstructions, size predictors), one of which
   * a parameter file chooses by name in a Patterns::Selection entry. A
   * member's name is written once, where it is registered; from the
   * registrations the registry makes the selection pattern and the help
   * text of the entry, declares the parameters of every member, creates the
   * member the parameter file names (with its parameters parsed), and gives
   * an object its name back (name_of(), which the family's name() calls).
   *
   * The family's base owns the registry, a function-local static of its
   * static registry() (constructed on first use, so that registrations from
   * any translation unit find it constructed), and names none of its
   * members: each member registers itself in its own .cc file with
   * SIGNORINI_REGISTER() or SIGNORINI_REGISTER_TEMPLATE(), as ASPECT's
   * plugins do. Static initialisation runs these in an unspecified order
   * across files, so every member has a rank: the choices are listed by
   * rank, and the lowest is the default.
   *
   * A member registered by add<T>() is constructed from @p Args and, if it
   * has parameters, provides static declare_parameters(ParameterHandler &)
   * and parse_parameters(ParameterHandler &), each entering its own section
   * (so the family's base class must not have members of these names);
   * add() with explicit functions covers other construction schemes.
   */
  template <typename Base, typename... Args>
  class Registry
  {
  public:
    /// Create a member and parse its parameters.
    using Creator =
      std::function<std::unique_ptr<Base>(ParameterHandler &, Args...)>;
    /// Declare a member's parameters (entering its own section).
    using Declarer = std::function<void(ParameterHandler &)>;
    /// The InputError message for choosing the member named by its argument
    /// where it is not implemented.
    using Refusal = std::function<std::string(const std::string &)>;

    /**
     * The family chosen by entry @p entry of section @p section; the help
     * string of the entry is "@p help: 'a' (description of a) or ...".
     * @p refusal words the choice of a member not implemented in this
     * instantiation (see add<T>()).
     */
    Registry(std::string section,
             std::string entry,
             std::string help,
             Refusal     refusal = {})
      : section(std::move(section))
      , entry(std::move(entry))
      , help(std::move(help))
      , refusal(std::move(refusal))
    {}

    /**
     * Register @p T under @p name, described by @p description in the help,
     * at position @p rank among the choices. A member whose static
     * is_implemented is false (in this instantiation) keeps its name and
     * parameters, so that a parameter file reads the same, but choosing it
     * is an InputError worded by the family's refusal.
     */
    template <typename T>
    Registry &
    add(const unsigned int rank,
        const std::string &name,
        const std::string &description)
    {
      static_assert(std::is_base_of_v<Base, T>, "not a member of the family");
      Declarer declare;
      if constexpr (internal::HasParameters<T>::value)
        declare = [](ParameterHandler &prm) { T::declare_parameters(prm); };
      Creator create;
      if constexpr (internal::IsImplemented<T>::value)
        create = [](ParameterHandler &prm,
                    Args... args) -> std::unique_ptr<Base> {
          auto member = std::make_unique<T>(args...);
          if constexpr (internal::HasParameters<T>::value)
            member->parse_parameters(prm);
          return member;
        };
      else
        {
          AssertThrow(refusal,
                      ExcMessage("no refusal for the unimplemented " + name));
          create = [message = refusal(name)](ParameterHandler &,
                                             Args...) -> std::unique_ptr<Base> {
            throw InputError(message);
          };
        }
      return add(rank, name, description, typeid(T), create, declare);
    }

    /// Register the member of dynamic type @p type at position @p rank with
    /// its own creation and declaration functions (@p declare may be empty:
    /// no parameters).
    Registry &
    add(const unsigned int    rank,
        const std::string    &name,
        const std::string    &description,
        const std::type_index type,
        Creator               create,
        Declarer              declare)
    {
      for (const auto &member : members)
        {
          AssertThrow(member.name != name && member.type != type,
                      ExcMessage("registered twice: " + name));
          AssertThrow(member.rank != rank,
                      ExcMessage(name + " and " + member.name +
                                 " have the same rank"));
        }
      const auto later =
        std::find_if(members.begin(), members.end(), [rank](const Member &m) {
          return m.rank > rank;
        });
      members.insert(later, {rank, name, description, type, create, declare});
      return *this;
    }

    /// "a|b|c" for Patterns::Selection, in the order of the ranks.
    std::string
    selection() const
    {
      std::string text;
      for (const auto &member : members)
        text += (text.empty() ? "" : "|") + member.name;
      return text;
    }

    /// Declare the selection entry and the parameters of every member.
    void
    declare_parameters(ParameterHandler &prm) const
    {
      Assert(!members.empty(), ExcInternalError());
      std::vector<std::pair<std::string, std::string>> choices;
      for (const auto &member : members)
        choices.emplace_back(member.name, member.description);
      prm.enter_subsection(section);
      prm.declare_entry(entry,
                        members.front().name,
                        Patterns::Selection(selection()),
                        help + ": " + internal::list_of_choices(choices) + ".");
      prm.leave_subsection();
      for (const auto &member : members)
        if (member.declare)
          member.declare(prm);
    }

    /// The name the selection entry holds.
    std::string
    selected(ParameterHandler &prm) const
    {
      prm.enter_subsection(section);
      const std::string name = prm.get(entry);
      prm.leave_subsection();
      return name;
    }

    /// The member the selection entry names, its parameters parsed.
    std::unique_ptr<Base>
    create(ParameterHandler &prm, Args... args) const
    {
      return create(selected(prm), prm, args...);
    }

    /// The member @p name, its parameters parsed from @p prm; throws
    /// InputError for an unknown name.
    std::unique_ptr<Base>
    create(const std::string &name, ParameterHandler &prm, Args... args) const
    {
      for (const auto &member : members)
        if (member.name == name)
          return member.create(prm, args...);
      throw InputError(section + "/" + entry + ": unknown choice <" + name +
                       ">, expected one of " + selection());
    }

    /// The name @p object was registered under (by its dynamic type).
    const std::string &
    name_of(const Base &object) const
    {
      for (const auto &member : members)
        if (member.type == std::type_index(typeid(object)))
          return member.name;
      AssertThrow(false, ExcMessage("a type not registered in its family"));
      return members.front().name;
    }

  private:
    /// A registered member.
    struct Member
    {
      /// Its position among the choices.
      unsigned int rank;
      /// Its value of the selection entry.
      std::string name;
      /// Its part of the help string.
      std::string description;
      /// Its dynamic type, for name_of().
      std::type_index type;
      /// Creates it and parses its parameters.
      Creator create;
      /// Declares its parameters (empty: none).
      Declarer declare;
    };

    /// Section of the selection entry.
    std::string section;
    /// Name of the selection entry.
    std::string entry;
    /// Beginning of its help string.
    std::string help;
    /// See the constructor.
    Refusal refusal;
    /// The members by rank, the default first.
    std::vector<Member> members;
  };



  /**
   * Adds the member @p T to the registry of its family @p Base when
   * constructed: the registration of a member is a namespace-scope object
   * in the member's .cc file (see SIGNORINI_REGISTER()), constructed during
   * static initialisation, like ASPECT's RegisterHelper.
   */
  template <typename Base, typename T>
  struct Registration
  {
    /// Register @p T as @p name at position @p rank (see Registry::add()).
    Registration(const unsigned int rank,
                 const std::string &name,
                 const std::string &description)
    {
      Base::registry().template add<T>(rank, name, description);
    }
  };
} // namespace Signorini

/**
 * Register the class @p member in the family of the class @p family as
 * @p name at position @p rank among the choices (the lowest: the default),
 * described by @p description in the help: in the member's .cc file, inside
 * namespace Signorini.
 */
#define SIGNORINI_REGISTER(family, member, rank, name, description) \
  static const ::Signorini::Registration<family, member>            \
    member##_registration(rank, name, description)

/**
 * SIGNORINI_REGISTER() for the class templates @p family<dim> and
 * @p member<dim>, in dimensions 2 and 3.
 */
#define SIGNORINI_REGISTER_TEMPLATE(family, member, rank, name, description) \
  static const ::Signorini::Registration<family<2>, member<2>>               \
    member##_registration_2d(rank, name, description);                       \
  static const ::Signorini::Registration<family<3>, member<3>>               \
    member##_registration_3d(rank, name, description)

#endif
