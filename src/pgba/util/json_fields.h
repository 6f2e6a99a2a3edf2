// to_json / from_json of an options struct from one list of (key, field) pairs, for the
// structs whose config keys are not their member names: an embedded SolverOptions or
// LossFunctionOptions (optim/) read and written under the flat keys configs have always
// used, e.g. BundleAdjusterOptions' "max_iterations" is solver.max_iterations. The struct's
// header defines the list once, both directions use it:
//
//   template <class Visit>
//   void JsonFields(BundleAdjusterOptions& o, Visit&& visit) {
//     visit("loss", o.loss.type);
//     visit("max_iterations", o.solver.max_iterations);
//   }
//   PGBA_JSON_FROM_FIELDS(BundleAdjusterOptions)
//
// Same behaviour as NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT: every listed key
// written, a key missing on reading keeps the field's value (the default, for get<T>()).
#pragma once

#include <nlohmann/json.hpp>

#define PGBA_JSON_FROM_FIELDS(Type)                                                                  \
  inline void to_json(nlohmann::json& j, const Type& o) {                                            \
    j = nlohmann::json::object();                                                                    \
    Type copy = o; /* JsonFields takes a mutable struct: one list serves both directions */          \
    JsonFields(copy, [&j](const char* key, const auto& field) { j[key] = field; });                  \
  }                                                                                                  \
  inline void from_json(const nlohmann::json& j, Type& o) {                                          \
    JsonFields(o, [&j](const char* key, auto& field) {                                               \
      if (j.contains(key)) j.at(key).get_to(field);                                                  \
    });                                                                                              \
  }
