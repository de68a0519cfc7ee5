#pragma once
// The project's one error for bad input: which field is wrong and what is
// wrong with it. Every library throws it at its boundary; the service turns
// it into JSON-RPC -32602 with the field, the programs print what().

#include <stdexcept>
#include <string>

namespace hfts {

/// A bad value of a named field. `field` is a path into the request or the
/// options ("start", "parameters.p_max", "contacts[0].normal",
/// "HandQueryOptions::neighbours"); what() is "<field>: <problem>", the
/// message form used across the project.
class InvalidArgument : public std::invalid_argument {
 public:
  InvalidArgument(std::string field, std::string problem)
      : std::invalid_argument(field + ": " + problem),
        field_(std::move(field)),
        problem_(std::move(problem)) {}

  const std::string& field() const { return field_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string field_;
  std::string problem_;
};

}  // namespace hfts
