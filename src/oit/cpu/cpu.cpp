// veil_oit_cpu: CPU double-precision references of the transparency techniques. The
// references live beside this file, one per technique family (composite.h, moments.h, ...).
namespace veil::oit::cpu {}
