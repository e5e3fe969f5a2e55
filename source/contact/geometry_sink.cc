// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#include <fmpm/contact/geometry_sink.h>
#include <fmpm/contact/manager.h>

namespace fmpm
{
  namespace Contact
  {
    template <int dim>
    void
    GeometrySink<dim>::reset(std::vector<MaterialField<dim>> &fields,
                             const NormalNeeds               &normal_needs,
                             const bool                       interface_state,
                             const MaterialPoints<dim>       &material_points,
                             const unsigned char *const       point_material,
                             const bool                       axisymmetric)
    {
      points          = &material_points;
      material        = point_material;
      using Index     = PropertyIndex<dim>;
      mass            = points->column(Index::mass);
      volume          = points->column(Index::volume);
      gradient_weight = volume;
      if (axisymmetric && normal_needs.volume_gradients)
        {
          // A = V/r_p (r_p > 0: the support builder refuses points on the
          // axis).
          area.resize(points->n_points());
          for (unsigned int k = 0; k < area.size(); ++k)
            area[k] = volume[k] / points->position[k][0];
          gradient_weight = area.data();
        }
      for (unsigned int d = 0; d < dim; ++d)
        initial_position[d] = points->column(Index::initial_position + d);
      gradient.clear();
      position.clear();
      displacement.clear();
      nodal_volume.clear();
      for (auto &field : fields)
        {
          if (normal_needs.volume_gradients)
            field.volume_gradient = 0;
          if (normal_needs.positions)
            field.position_moment = 0;
          if (interface_state)
            {
              field.displacement_moment = 0;
              field.volume              = 0;
              nodal_volume.push_back(field.volume.begin());
            }
          for (unsigned int d = 0; d < dim; ++d)
            {
              if (normal_needs.volume_gradients)
                gradient.push_back(field.volume_gradient.block(d).begin());
              if (normal_needs.positions)
                position.push_back(field.position_moment.block(d).begin());
              if (interface_state)
                displacement.push_back(
                  field.displacement_moment.block(d).begin());
            }
        }
    }



    template <int dim>
    void
    GeometrySink<dim>::compress(MaterialField<dim> &field,
                                const NormalNeeds  &normal_needs,
                                const bool          interface_state)
    {
      if (normal_needs.volume_gradients)
        field.volume_gradient.compress(VectorOperation::add);
      if (normal_needs.positions)
        field.position_moment.compress(VectorOperation::add);
      if (interface_state)
        {
          field.displacement_moment.compress(VectorOperation::add);
          field.volume.compress(VectorOperation::add);
        }
    }



    template class GeometrySink<2>;
    template class GeometrySink<3>;
  } // namespace Contact
} // namespace fmpm
