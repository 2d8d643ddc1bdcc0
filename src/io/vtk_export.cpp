#include "io/vtk_export.h"

#include "base/atomic_file.h"
#include "base/error.h"

#include <vtkDataArray.h>
#include <vtkErrorCode.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkStringArray.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLImageDataWriter.h>

#include <cstring>

namespace veil::io {

bool vtiSupported() { return true; }

void requireVti(const std::filesystem::path&) {}

void writeVti(const std::filesystem::path& path, const DenseGrid& grid) {
    const std::size_t n = std::size_t(grid.dims[0]) * grid.dims[1] * grid.dims[2];
    VEIL_CHECK(grid.components == 1 || grid.components == 3, "vti '{}': {} components per point",
               path.string(), grid.components);
    VEIL_CHECK(n > 0 && grid.values.size() == n * grid.components,
               "vti '{}': {} values for a {}x{}x{} grid of {} component(s)", path.string(),
               grid.values.size(), grid.dims[0], grid.dims[1], grid.dims[2], grid.components);
    vtkNew<vtkImageData> image;
    image->SetDimensions(grid.dims[0], grid.dims[1], grid.dims[2]);
    image->SetOrigin(grid.origin[0], grid.origin[1], grid.origin[2]);
    image->SetSpacing(grid.spacing[0], grid.spacing[1], grid.spacing[2]);
    vtkNew<vtkFloatArray> values;
    values->SetName(grid.name.c_str());
    values->SetNumberOfComponents(grid.components);
    values->SetNumberOfTuples(static_cast<vtkIdType>(n));
    std::copy(grid.values.begin(), grid.values.end(), values->GetPointer(0));
    if (grid.components == 3)
        image->GetPointData()->SetVectors(values);
    else
        image->GetPointData()->SetScalars(values);
    for (const auto& [name, more] : grid.moreScalars) {
        VEIL_CHECK(more.size() == n, "vti '{}': array '{}' has {} values for {} points",
                   path.string(), name, more.size(), n);
        vtkNew<vtkFloatArray> a;
        a->SetName(name.c_str());
        a->SetNumberOfTuples(static_cast<vtkIdType>(n));
        std::copy(more.begin(), more.end(), a->GetPointer(0));
        image->GetPointData()->AddArray(a);
    }
    for (const auto& [key, value] : grid.fieldData) {
        vtkNew<vtkStringArray> a;
        a->SetName(key.c_str());
        a->InsertNextValue(value);
        image->GetFieldData()->AddArray(a);
    }
    writeFileAtomically(path, [&](const std::filesystem::path& tmp) {
        vtkNew<vtkXMLImageDataWriter> writer;
        writer->SetFileName(tmp.string().c_str());
        writer->SetInputData(image);
        writer->SetDataModeToAppended();
        writer->SetCompressorTypeToZLib();
        // VTK reports a full disk through the error code, prints it and still returns 1;
        // its own printing is switched off so the error ends as one line.
        const bool warnings = vtkObject::GetGlobalWarningDisplay();
        vtkObject::GlobalWarningDisplayOff();
        const bool ok = writer->Write() == 1;
        vtkObject::SetGlobalWarningDisplay(warnings);
        const unsigned long code = writer->GetErrorCode();
        // Below FirstVTKErrorCode the code is an errno value (28: ENOSPC).
        VEIL_CHECK(ok && code == vtkErrorCode::NoError, "cannot write '{}': {}", path.string(),
                   code == vtkErrorCode::NoError ? std::string("VTK writer failed")
                   : code < vtkErrorCode::FirstVTKErrorCode
                       ? std::string(std::strerror(static_cast<int>(code)))
                       : fmt::format("VTK error code {}", code));
    });
}

DenseGrid readVti(const std::filesystem::path& path) {
    VEIL_CHECK(std::filesystem::is_regular_file(path), "cannot read '{}': no such file",
               path.string());
    vtkNew<vtkXMLImageDataReader> reader;
    reader->SetFileName(path.string().c_str());
    reader->Update();
    vtkImageData* image = reader->GetOutput();
    VEIL_CHECK(image && image->GetPointData()->GetNumberOfArrays() > 0, "'{}' holds no image data",
               path.string());
    DenseGrid g;
    int dims[3];
    image->GetDimensions(dims);
    double o[3], s[3];
    image->GetOrigin(o);
    image->GetSpacing(s);
    for (int i = 0; i < 3; ++i)
        g.dims[i] = dims[i], g.origin[i] = o[i], g.spacing[i] = s[i];
    vtkDataArray* a = image->GetPointData()->GetArray(0);
    g.name = a->GetName() ? a->GetName() : "";
    g.components = a->GetNumberOfComponents();
    VEIL_CHECK(g.components == 1 || g.components == 3, "'{}': {} components per point",
               path.string(), g.components);
    g.values.resize(static_cast<std::size_t>(a->GetNumberOfTuples()) * g.components);
    for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
        for (int c = 0; c < g.components; ++c)
            g.values[static_cast<std::size_t>(i) * g.components + c] =
                static_cast<float>(a->GetComponent(i, c));
    for (int k = 1; k < image->GetPointData()->GetNumberOfArrays(); ++k) {
        vtkDataArray* more = image->GetPointData()->GetArray(k);
        if (!more || more->GetNumberOfComponents() != 1) continue;
        std::vector<float> v(static_cast<std::size_t>(more->GetNumberOfTuples()));
        for (vtkIdType i = 0; i < more->GetNumberOfTuples(); ++i)
            v[static_cast<std::size_t>(i)] = static_cast<float>(more->GetComponent(i, 0));
        g.moreScalars.emplace_back(more->GetName() ? more->GetName() : "", std::move(v));
    }
    vtkFieldData* fields = image->GetFieldData();
    for (int k = 0; fields && k < fields->GetNumberOfArrays(); ++k)
        if (auto* s = vtkStringArray::SafeDownCast(fields->GetAbstractArray(k));
            s && s->GetNumberOfValues() > 0)
            g.fieldData.emplace_back(s->GetName() ? s->GetName() : "", s->GetValue(0));
    return g;
}

} // namespace veil::io
