#include <deal.II/base/exceptions.h>

#include <signorini/csv_table.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace Signorini
{
  namespace
  {
    /// Ten significant digits: enough for the regression comparisons.
    std::string
    format(const double value)
    {
      char text[32];
      std::snprintf(text, sizeof(text), "%.10g", value);
      return text;
    }

    void
    add_column(std::vector<std::string> &columns, const std::string &column)
    {
      if (std::find(columns.begin(), columns.end(), column) == columns.end())
        columns.push_back(column);
    }
  } // namespace



  void
  CsvTable::add_value(const std::string &column, const std::string &value)
  {
    add_column(columns, column);
    current[column] = value;
  }



  void
  CsvTable::add_value(const std::string &column, const double value)
  {
    add_value(column, format(value));
  }



  void
  CsvTable::set_value(const unsigned int row,
                      const std::string &column,
                      const double       value)
  {
    AssertIndexRange(row, rows.size());
    add_column(columns, column);
    rows[row][column] = format(value);
  }



  void
  CsvTable::add_value(const std::string &column, const long long value)
  {
    add_value(column, std::to_string(value));
  }



  void
  CsvTable::add_value(const std::string &column, const unsigned int value)
  {
    add_value(column, std::to_string(value));
  }



  void
  CsvTable::end_row()
  {
    rows.push_back(current);
    current.clear();
  }



  void
  CsvTable::write(const std::string &filename) const
  {
    std::ofstream out(filename);
    write(out);
    out.close();
    if (!out)
      throw std::runtime_error("cannot write <" + filename + ">");
  }



  void
  CsvTable::write(std::ostream &out) const
  {
    for (unsigned int c = 0; c < columns.size(); ++c)
      out << (c ? "," : "") << columns[c];
    out << '\n';
    for (const auto &row : rows)
      {
        for (unsigned int c = 0; c < columns.size(); ++c)
          {
            const auto it = row.find(columns[c]);
            out << (c ? "," : "") << (it != row.end() ? it->second : "");
          }
        out << '\n';
      }
  }



  std::vector<std::string>
  CsvTable::column(const std::string &name) const
  {
    std::vector<std::string> values;
    for (const auto &row : rows)
      {
        const auto it = row.find(name);
        values.push_back(it == row.end() ? "" : it->second);
      }
    return values;
  }



  std::string
  CsvTable::last(const std::string &column) const
  {
    if (rows.empty())
      return "";
    const auto it = rows.back().find(column);
    return it == rows.back().end() ? "" : it->second;
  }
} // namespace Signorini
