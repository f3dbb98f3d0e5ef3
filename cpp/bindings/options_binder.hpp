// Binding an options struct of the core as a Python class (internal to cpp/bindings): every field
// declared once — its Python name, how it converts, its docstring — and from that list the class
// gets properties, a keyword constructor that starts from `T{}` (so every default comes from the
// struct's default member initialisers) and rejects unknown names with TypeError, a __repr__
// listing every field, `_fields` (the names in order) and a class docstring listing the fields
// with their defaults. Enum fields read and write the core's names through its parse/toString
// functions, so a bad name raises the core's InvalidInput with its message.
// Preconditions: called with the GIL held, while the module is being initialised.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "binding_helpers.hpp"

namespace curvedslicer::bindings {

/// Accessors of a (possibly nested) member, for OptionsClass fields:
/// member(&LayerJobOptions::voxelize, &VoxelizeOptions::voxelSize).
template <class T, class V>
auto member(V T::*field) {
  return [field](T& t) -> V& { return t.*field; };
}
template <class T, class M, class V>
auto member(M T::*outer, V M::*inner) {
  return [outer, inner](T& t) -> V& { return (t.*outer).*inner; };
}

/// What a Python value of C++ type V must look like, for TypeError messages.
template <class V>
std::string expectedValue() {
  if constexpr (std::is_same_v<V, bool>) {
    return "True or False";
  } else if constexpr (std::is_integral_v<V>) {
    return "an integer";
  } else if constexpr (std::is_floating_point_v<V>) {
    return "a number";
  } else if constexpr (std::is_same_v<V, std::string>) {
    return "a string";
  } else if constexpr (std::is_same_v<V, std::vector<int>>) {
    return "a list of integers";
  } else if constexpr (std::is_same_v<V, std::vector<double>>) {
    return "a sequence of numbers";
  } else if constexpr (std::is_base_of_v<py::array, V>) {
    return "an array of numbers";
  } else {
    return "a " + std::string(py::str(py::type::of<V>().attr("__name__"))) + " object";
  }
}

/// `value` as V; TypeError "<Class.field> needs <kind>: <repr> (<type>); pass <kind>" if not.
template <class V>
V castOption(py::handle value, const std::string& where) {
  try {
    return value.cast<V>();
  } catch (const py::cast_error&) {
    const std::string kind = expectedValue<V>();
    throw py::type_error(where + " needs " + kind + ": " + std::string(py::repr(value)) + " (" +
                         std::string(py::str(value.get_type().attr("__name__"))) + "); pass " +
                         kind);
  }
}

/// A point or direction from any sequence of 3 numbers (part frame, mm).
Vec3 castVec3(py::handle value, const std::string& where);
/// A mesh from (vertices (n, 3), triangles (m, 3)) or a dict with "vertices" and "triangles".
TriMesh castMesh(py::handle value, const std::string& where);
/// "mesh(<n> vertices, <m> triangles)".
std::string describeMesh(const TriMesh& mesh);

template <class T>
class OptionsClass {
 public:
  OptionsClass(py::module_& m, const char* name, std::string doc)
      : cls_(m, name), name_(name), doc_(std::move(doc)), fields_(std::make_shared<Fields>()) {}

  py::class_<T>& cls() { return cls_; }

  /// A number, bool, string or list of ints, converted by pybind11 (TypeError if it cannot).
  template <class Access>
  OptionsClass& value(const char* name, Access access, const char* doc) {
    using V = std::remove_reference_t<std::invoke_result_t<Access, T&>>;
    const std::string where = qualified(name);
    return add(
        name, doc, [access](py::object self) { return py::cast(access(self.cast<T&>())); },
        [access, where](T& t, py::handle v) { access(t) = castOption<V>(v, where); });
  }

  /// An enum as its core name: `format(e)` reads, `parse(text)` writes (InvalidInput if unknown).
  template <class Access, class Parse, class Format>
  OptionsClass& choice(const char* name, Access access, Parse parse, Format format,
                       const char* doc) {
    const std::string where = qualified(name);
    return add(
        name, doc,
        [access, format](py::object self) {
          return py::object(py::str(std::string(format(access(self.cast<T&>())))));
        },
        [access, parse, where](T& t, py::handle v) {
          access(t) = parse(castOption<std::string>(v, where));
        });
  }

  /// A Vec3 as a tuple of 3 floats; any sequence of 3 numbers writes it.
  template <class Access>
  OptionsClass& vec3(const char* name, Access access, const char* doc) {
    const std::string where = qualified(name);
    return add(
        name, doc,
        [access](py::object self) {
          const Vec3& v = access(self.cast<T&>());
          return py::object(py::make_tuple(v.x(), v.y(), v.z()));
        },
        [access, where](T& t, py::handle v) { access(t) = castVec3(v, where); });
  }

  /// A TriMesh: reads as {vertices, triangles, face_ids}; writes from (vertices, triangles) or
  /// such a dict, passed through `prepare` (e.g. cleanMesh).
  template <class Access>
  OptionsClass& mesh(const char* name, Access access, const char* doc,
                     std::function<TriMesh(TriMesh)> prepare = {}) {
    const std::string where = qualified(name);
    add(
        name, doc,
        [access](py::object self) { return py::object(meshDict(access(self.cast<T&>()))); },
        [access, where, prepare](T& t, py::handle v) {
          TriMesh m = castMesh(v, where);
          access(t) = prepare ? prepare(std::move(m)) : std::move(m);
        });
    fields_->back().repr = [access](py::object self) {
      return describeMesh(access(self.cast<T&>()));
    };
    return *this;
  }

  /// A bound options struct, read by reference (so `options.planner.bead_spacing = 2` changes
  /// `options`); writing copies the value.
  template <class Access>
  OptionsClass& nested(const char* name, Access access, const char* doc) {
    using N = std::remove_reference_t<std::invoke_result_t<Access, T&>>;
    const std::string where = qualified(name);
    return add(
        name, doc,
        [access](py::object self) {
          return py::cast(&access(self.cast<T&>()), py::return_value_policy::reference_internal,
                          self);
        },
        [access, where](T& t, py::handle v) { access(t) = castOption<N>(v, where); });
  }

  /// An optional bound struct: None or a copy (assign a new value to change it).
  template <class Access>
  OptionsClass& optional(const char* name, Access access, const char* doc) {
    using O = std::remove_reference_t<std::invoke_result_t<Access, T&>>;
    using N = typename O::value_type;
    const std::string where = qualified(name);
    return add(
        name, doc,
        [access](py::object self) {
          const O& o = access(self.cast<T&>());
          return o ? py::cast(*o, py::return_value_policy::copy) : py::object(py::none());
        },
        [access, where](T& t, py::handle v) {
          if (v.is_none()) {
            access(t).reset();
          } else {
            access(t) = castOption<N>(v, where);
          }
        });
  }

  /// Defines __init__(**fields), __repr__, _fields and the class docstring. Call once, last.
  void finish();

 private:
  struct Field {
    std::string name;
    std::function<py::object(py::object)> get;
    std::function<void(T&, py::handle)> set;
    std::function<std::string(py::object)> repr;  // empty: repr(get(self))
  };
  using Fields = std::vector<Field>;

  std::string qualified(const char* field) const { return name_ + "." + field; }

  template <class Get, class Set>
  OptionsClass& add(const char* name, const char* doc, Get get, Set set) {
    fields_->push_back(Field{name, get, set, {}});
    docs_.emplace_back(doc);
    cls_.def_property(name,
                      py::cpp_function([get](py::object self) { return get(std::move(self)); }),
                      py::cpp_function([set](T& t, py::handle v) { set(t, v); }), doc);
    return *this;
  }

  static std::string fieldRepr(const Field& f, const py::object& self) {
    return f.repr ? f.repr(self) : std::string(py::repr(f.get(self)));
  }

  py::class_<T> cls_;
  std::string name_;
  std::string doc_;
  std::vector<std::string> docs_;
  std::shared_ptr<Fields> fields_;
};

template <class T>
void OptionsClass<T>::finish() {
  const std::shared_ptr<Fields> fields = fields_;
  const std::string className = name_;
  const std::string initDoc =
      "Every field by keyword (see the class docstring); the others keep "
      "the defaults of the core's " +
      className + "{}.";
  cls_.def(py::init([fields, className](const py::kwargs& kwargs) {
             T t{};
             for (const auto& [key, value] : kwargs) {
               const std::string name = py::str(key);
               const Field* field = nullptr;
               for (const Field& f : *fields) {
                 if (f.name == name) field = &f;
               }
               if (field == nullptr) {
                 std::string names;
                 for (const Field& f : *fields) names += (names.empty() ? "" : ", ") + f.name;
                 throw py::type_error("unknown option of " + className + ": '" + name +
                                      "'; use one of " + names);
               }
               field->set(t, value);
             }
             return t;
           }),
           initDoc.c_str());
  cls_.def("__repr__", [fields, className](py::object self) {
    std::string text = className + "(";
    for (std::size_t i = 0; i < fields->size(); ++i) {
      text += (i ? ", " : "") + (*fields)[i].name + "=" + fieldRepr((*fields)[i], self);
    }
    return text + ")";
  });
  py::list names;
  std::string doc = doc_ + "\n\nFields (keyword arguments of the constructor), with defaults:\n";
  const py::object defaults = py::cast(T{});
  for (std::size_t i = 0; i < fields->size(); ++i) {
    const Field& f = (*fields)[i];
    names.append(f.name);
    doc += "  " + f.name + " = " + fieldRepr(f, defaults) + ": " + docs_[i] + "\n";
  }
  cls_.attr("_fields") = py::tuple(names);
  cls_.attr("__doc__") = doc;
}

}  // namespace curvedslicer::bindings
