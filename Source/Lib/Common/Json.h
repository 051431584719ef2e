#pragma once
// A small JSON reader (RFC 8259, plus the tokens Infinity and inf for an infinite far plane) that
// remembers the line of every value, so that errors in camera files can say where; and helpers to
// write JSON numbers that read back to the same double.
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace vs {

class JsonValue {
public:
  enum class Type { Null, Bool, Number, String, Array, Object };

  Type type = Type::Null;
  int line = 0;  // 1-based line where the value starts
  bool boolean = false;
  double number = 0;
  std::string text;                              // String
  std::vector<JsonValue> items;                  // Array
  std::vector<std::pair<std::string, JsonValue>> members;  // Object, in file order

  // Member of an object, or nullptr.
  const JsonValue* find(const std::string& key) const;
  const char* typeName() const;
};

// Parses `text` (named `source` in messages). Throws InputError "source:line: ..." on malformed
// input; depth of nesting is limited to 64.
JsonValue parseJson(const std::string& text, const std::string& source);

// Shortest decimal that reads back to the same double ("inf" for +infinity is written as Infinity).
std::string jsonNumber(double value);
// A JSON string literal with the needed escapes.
std::string jsonString(const std::string& value);

}  // namespace vs
