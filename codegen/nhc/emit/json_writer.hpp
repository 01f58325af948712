#pragma once
/// \file json_writer.hpp
/// \brief A minimal streaming JSON writer (objects, arrays, strings, numbers, booleans, null),
/// enough for nhc's machine-readable outputs without another dependency.

#include <ostream>
#include <string>
#include <vector>

namespace nhc {

class JsonWriter {
 public:
  explicit JsonWriter(std::ostream& out) : out_(out) {}

  JsonWriter& begin_object();
  JsonWriter& end_object();
  JsonWriter& begin_array();
  JsonWriter& end_array();
  /// Key inside an object; the next value call writes its value.
  JsonWriter& key(const std::string& k);
  JsonWriter& value(const std::string& s);
  JsonWriter& value(const char* s) { return value(std::string(s)); }
  JsonWriter& value(double d);  ///< non-finite values are written as null
  JsonWriter& value(long long i);
  JsonWriter& value(int i) { return value(static_cast<long long>(i)); }
  JsonWriter& value(bool b);
  JsonWriter& null();

  static std::string quote(const std::string& s);

 private:
  void before_value();
  void newline();
  std::ostream& out_;
  struct Level {
    bool object;
    bool empty;
  };
  std::vector<Level> stack_;
  bool after_key_ = false;
};

}  // namespace nhc
