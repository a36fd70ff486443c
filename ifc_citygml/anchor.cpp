// Placeholder so the module library has a source until its first stage lands.
namespace c3d { int ifc_citygml_module_anchor = 0; }
