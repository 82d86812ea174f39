#pragma once
// A scalar function of time (loads, references, inputs). core only sees this interface;
// io compiles the .dat expressions (muParser) into implementations.
#include <memory>
#include <string>

namespace flexmb::core {

class TimeFunction {
 public:
  virtual ~TimeFunction() = default;
  virtual double value(double t) const = 0;
  virtual std::string text() const = 0;  // the source expression, for messages and echo
};

using TimeFunctionPtr = std::shared_ptr<const TimeFunction>;

}  // namespace flexmb::core
