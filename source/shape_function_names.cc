// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

// The names of the shape functions in the parameter file (Shape
// function/Type).

#include <fmpm/shape_function.h>

#include <deal.II/base/exceptions.h>

#include <string>

namespace fmpm
{
  namespace ShapeFunction
  {
    Type
    parse(const std::string &name)
    {
      if (name == "classic")
        return Type::classic;
      if (name == "ugimp")
        return Type::ugimp;
      if (name == "cpgimp")
        return Type::cpgimp;
      if (name == "cpdi")
        return Type::cpdi;
      if (name == "b2spline")
        return Type::b2spline;
      if (name == "b3spline")
        return Type::b3spline;
      if (name == "b2gimp")
        return Type::b2gimp;
      if (name == "b2cpdi")
        return Type::b2cpdi;
      AssertThrow(false,
                  ExcMessage("Shape function/Type = <" + name +
                             "> is not one of " + pattern() + "."));
      return Type::classic;
    }



    std::string
    parameter_name(const Type type)
    {
      switch (type)
        {
          case Type::classic:
            return "classic";
          case Type::ugimp:
            return "ugimp";
          case Type::cpgimp:
            return "cpgimp";
          case Type::cpdi:
            return "cpdi";
          case Type::b2spline:
            return "b2spline";
          case Type::b3spline:
            return "b3spline";
          case Type::b2gimp:
            return "b2gimp";
          case Type::b2cpdi:
            return "b2cpdi";
        }
      return "classic";
    }
  } // namespace ShapeFunction
} // namespace fmpm
