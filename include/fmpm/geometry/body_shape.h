// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_geometry_body_shape_h
#define fmpm_geometry_body_shape_h

#include <fmpm/geometry/shape.h>
#include <fmpm/parameters.h>

#include <deal.II/base/parameter_handler.h>

namespace fmpm
{
  namespace Geometry
  {
    /**
     * @brief Declare 'Shape' and 'File name' of one 'Body N' (the caller
     * enters the subsection).
     */
    void
    declare_body_shape_parameters(ParameterHandler &prm);

    /**
     * @brief Read 'Shape' and 'File name' into @p body and build its shape
     * once, so that a bad formula, a missing file, a self-intersecting
     * polygon or an open surface stops the parsing (and --validate) with a
     * message naming @p where. Call after the body's other entries are
     * read (the level sets use its 'Function constants').
     */
    void
    parse_body_shape_parameters(ParameterHandler  &prm,
                                BodyParameters    &body,
                                const unsigned int dim,
                                const std::string &where);

    /**
     * @brief The region of @p body: its shape formula, or the box, sphere or
     * ellipsoid of its Center and Half lengths. A body from a volume mesh
     * (BodyParameters::from_mesh) has the region its cells cover.
     */
    template <int dim>
    std::unique_ptr<Shape<dim>>
    create_body_shape(const BodyParameters &body, const std::string &where);

    /** The regions of the scene's bodies, in the order of their numbers. */
    template <int dim>
    std::vector<std::unique_ptr<Shape<dim>>>
    create_body_shapes(const std::vector<BodyParameters> &bodies);
  } // namespace Geometry
} // namespace fmpm

#endif
