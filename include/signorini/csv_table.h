#ifndef signorini_csv_table_h
#define signorini_csv_table_h

#include <map>
#include <ostream>
#include <string>
#include <vector>

namespace Signorini
{
  /**
   * A table with named columns written as comma separated values, one row
   * per cycle. Columns appear in the order they are first set; the file is
   * rewritten after each row so that a failure in a later cycle leaves the
   * completed rows on disk.
   */
  class CsvTable
  {
  public:
    void
    add_value(const std::string &column, const std::string &value);

    void
    add_value(const std::string &column, const double value);

    void
    add_value(const std::string &column, const long long value);

    void
    add_value(const std::string &column, const unsigned int value);

    /// Set @p column of the completed row @p row (results known only later).
    void
    set_value(const unsigned int row,
              const std::string &column,
              const double       value);

    /// Close the current row.
    void
    end_row();

    /// Write the table to @p filename; throws std::runtime_error naming it
    /// if it cannot be written.
    void
    write(const std::string &filename) const;

    /// Write the table to @p out.
    void
    write(std::ostream &out) const;

    /// Values of @p column in all completed rows ("" where unset).
    std::vector<std::string>
    column(const std::string &name) const;

    /// Value of @p column in the last completed row ("" if unset).
    std::string
    last(const std::string &column) const;

  private:
    std::vector<std::string>                        columns;
    std::vector<std::map<std::string, std::string>> rows;
    std::map<std::string, std::string>              current;
  };
} // namespace Signorini

#endif
