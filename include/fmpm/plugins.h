// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 by the fmpm authors

#ifndef fmpm_plugins_h
#define fmpm_plugins_h

#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>

#include <functional>
#include <map>
#include <memory>
#include <string>

namespace fmpm
{
  namespace Plugins
  {
    using namespace dealii;

    /**
     * @brief Base class of every plugin interface.
     *
     * Provides the no-op hooks that the Simulator calls on every plugin:
     * parse_parameters() once after reading the scene, initialize() once
     * after the mesh and the material points exist, and save()/load() for
     * checkpoints. Plugins override only what they need.
     */
    class InterfaceBase
    {
    public:
      virtual ~InterfaceBase() = default;

      /** @brief Read this plugin's parameters from its subsection. */
      virtual void
      parse_parameters(ParameterHandler &)
      {}

      /** @brief Called once the Simulator is set up. */
      virtual void
      initialize()
      {}

      /** @brief Store plugin state that must survive a restart. */
      virtual void
      save(std::map<std::string, std::string> &) const
      {}

      /** @brief Restore what save() stored. */
      virtual void
      load(const std::map<std::string, std::string> &)
      {}
    };

    /**
     * @brief The list of plugins of one system, e.g. all constitutive models.
     *
     * Each plugin registers its name, its user-facing description, a function
     * declaring its parameters in a subsection named after the plugin (first
     * letter capitalized), and a factory.
     *
     * @tparam InterfaceType the system's interface class.
     */
    template <typename InterfaceType>
    class Registry
    {
    public:
      struct Entry
      {
        std::string                                     description;
        std::function<void(ParameterHandler &)>         declare_parameters;
        std::function<std::unique_ptr<InterfaceType>()> create;
      };

      /** @brief The one registry of this system. */
      static Registry &
      instance()
      {
        static Registry registry;
        return registry;
      }

      /** @brief Add a plugin; called from FMPM_REGISTER_* at load time. */
      void
      register_plugin(
        const std::string                                     &name,
        const std::string                                     &description,
        const std::function<void(ParameterHandler &)>         &declare,
        const std::function<std::unique_ptr<InterfaceType>()> &create)
      {
        AssertThrow(entries.find(name) == entries.end(),
                    ExcMessage("Plugin <" + name + "> registered twice."));
        entries[name] = Entry{description, declare, create};
      }

      /** @brief "a|b|c": the names for a Patterns::Selection. */
      std::string
      pattern() const
      {
        std::string result;
        for (const auto &entry : entries)
          result += (result.empty() ? "" : "|") + entry.first;
        return result;
      }

      /** @brief The names with their descriptions, for parameter docs. */
      std::string
      documentation() const
      {
        std::string result;
        for (const auto &entry : entries)
          result += "'" + entry.first + "': " + entry.second.description + " ";
        return result;
      }

      /** @brief Declare every plugin's parameters in its own subsection. */
      void
      declare_parameters(ParameterHandler &prm) const
      {
        for (const auto &entry : entries)
          if (entry.second.declare_parameters)
            {
              prm.enter_subsection(subsection_name(entry.first));
              entry.second.declare_parameters(prm);
              prm.leave_subsection();
            }
      }

      /**
       * @brief Create the plugin @p name and let it parse its subsection.
       */
      std::unique_ptr<InterfaceType>
      create(const std::string &name, ParameterHandler &prm) const
      {
        const auto entry = entries.find(name);
        AssertThrow(entry != entries.end(),
                    ExcMessage("Unknown plugin <" + name +
                               ">. Allowed names: " + pattern()));
        std::unique_ptr<InterfaceType> plugin = entry->second.create();
        if (entry->second.declare_parameters)
          {
            prm.enter_subsection(subsection_name(name));
            plugin->parse_parameters(prm);
            prm.leave_subsection();
          }
        else
          plugin->parse_parameters(prm);
        return plugin;
      }

      /** @brief "neo hookean" -> "Neo hookean", the ParameterHandler style. */
      static std::string
      subsection_name(std::string name)
      {
        if (!name.empty())
          name[0] = static_cast<char>(std::toupper(name[0]));
        return name;
      }

    private:
      std::map<std::string, Entry> entries;
    };

    /**
     * @brief Registers a plugin class for dim = 2 and 3 at load time.
     */
    template <template <int> class InterfaceType,
              template <int>
              class PluginType>
    struct RegisterForBothDimensions
    {
      RegisterForBothDimensions(const std::string &name,
                                const std::string &description)
      {
        Registry<InterfaceType<2>>::instance().register_plugin(
          name, description, &PluginType<2>::declare_parameters, []() {
            return std::make_unique<PluginType<2>>();
          });
        Registry<InterfaceType<3>>::instance().register_plugin(
          name, description, &PluginType<3>::declare_parameters, []() {
            return std::make_unique<PluginType<3>>();
          });
      }
    };
  } // namespace Plugins
} // namespace fmpm

/**
 * Registers PluginClass as NAME in the system INTERFACE (both dimensions).
 * Used by the FMPM_REGISTER_* macros of each plugin system.
 */
#define FMPM_REGISTER_PLUGIN(INTERFACE, CLASSNAME, NAME, DESCRIPTION)      \
  namespace                                                                \
  {                                                                        \
    const ::fmpm::Plugins::RegisterForBothDimensions<INTERFACE, CLASSNAME> \
      fmpm_plugin_registration_##CLASSNAME(NAME, DESCRIPTION);             \
  }

#endif
