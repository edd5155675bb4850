# Vesuvius default transfer functions (installed as share/vesuvius/transfer-functions.tf).
# One block per species name, by kind, over a typical range in the models' usual units.
# A .vsv file stores its own (ranges from its data); copy and edit these and pass them
# with --tf to vsv-render or vsv-play: a block is found by the species' name.
# Lines: kind, colormap (viridis magma cividis clouds rain ice snow greys), range LO HI,
# scale linear|log, opacity P0 P1 ... (evenly spaced over the range).

# cloud water, kg/kg
species CLW
kind cloud
colormap clouds
range 0 0.001
scale linear
opacity 0 0.05 0.2 0.45 0.8

species QCLOUD
kind cloud
colormap clouds
range 0 0.001
scale linear
opacity 0 0.05 0.2 0.45 0.8

species QC
kind cloud
colormap clouds
range 0 0.001
scale linear
opacity 0 0.05 0.2 0.45 0.8

# rain water, kg/kg
species RNW
kind rain
colormap rain
range 0 0.0005
scale linear
opacity 0 0.05 0.2 0.45 0.8

species QRAIN
kind rain
colormap rain
range 0 0.0005
scale linear
opacity 0 0.05 0.2 0.45 0.8

species QR
kind rain
colormap rain
range 0 0.0005
scale linear
opacity 0 0.05 0.2 0.45 0.8

# ice and graupel, kg/kg
species ICE
kind ice
colormap ice
range 0 0.0003
scale linear
opacity 0 0.05 0.2 0.45 0.8

species QICE
kind ice
colormap ice
range 0 0.0003
scale linear
opacity 0 0.05 0.2 0.45 0.8

species QI
kind ice
colormap ice
range 0 0.0003
scale linear
opacity 0 0.05 0.2 0.45 0.8

species QGRAUP
kind ice
colormap ice
range 0 0.0003
scale linear
opacity 0 0.05 0.2 0.45 0.8

species GRAUPEL
kind ice
colormap ice
range 0 0.0003
scale linear
opacity 0 0.05 0.2 0.45 0.8

# snow, kg/kg
species SNOW
kind snow
colormap snow
range 0 0.0005
scale linear
opacity 0 0.05 0.2 0.45 0.8

species QSNOW
kind snow
colormap snow
range 0 0.0005
scale linear
opacity 0 0.05 0.2 0.45 0.8

species QS
kind snow
colormap snow
range 0 0.0005
scale linear
opacity 0 0.05 0.2 0.45 0.8

# water vapour, kg/kg: a faint veil
species Q
kind vapour
colormap cividis
range 0 0.02
scale linear
opacity 0 0.005 0.01 0.02 0.04

species QVAPOR
kind vapour
colormap cividis
range 0 0.02
scale linear
opacity 0 0.005 0.01 0.02 0.04

species QV
kind vapour
colormap cividis
range 0 0.02
scale linear
opacity 0 0.005 0.01 0.02 0.04

# ozone, ppm
species O3
kind ozone
colormap viridis
range 0 0.12
scale linear
opacity 0 0.05 0.2 0.45 0.8

# nitrogen oxides, ppm
species NO
kind nox
colormap magma
range 0 0.05
scale linear
opacity 0 0.05 0.2 0.45 0.8

species NO2
kind nox
colormap magma
range 0 0.05
scale linear
opacity 0 0.05 0.2 0.45 0.8

species NOX
kind nox
colormap magma
range 0 0.05
scale linear
opacity 0 0.05 0.2 0.45 0.8

# particulate matter, ug/m3
species PM25
kind pm
colormap cividis
range 0 100
scale linear
opacity 0 0.05 0.2 0.45 0.8

species PM10
kind pm
colormap cividis
range 0 100
scale linear
opacity 0 0.05 0.2 0.45 0.8

species PSO4
kind pm
colormap cividis
range 0 100
scale linear
opacity 0 0.05 0.2 0.45 0.8

species PNO3
kind pm
colormap cividis
range 0 100
scale linear
opacity 0 0.05 0.2 0.45 0.8

species PNH4
kind pm
colormap cividis
range 0 100
scale linear
opacity 0 0.05 0.2 0.45 0.8

species POA
kind pm
colormap cividis
range 0 100
scale linear
opacity 0 0.05 0.2 0.45 0.8

species PEC
kind pm
colormap cividis
range 0 100
scale linear
opacity 0 0.05 0.2 0.45 0.8

species SOA
kind pm
colormap cividis
range 0 100
scale linear
opacity 0 0.05 0.2 0.45 0.8

# smoke, ug/m3
species SMOKE
kind smoke
colormap greys
range 0 200
scale linear
opacity 0 0.05 0.2 0.45 0.8

species BC
kind smoke
colormap greys
range 0 200
scale linear
opacity 0 0.05 0.2 0.45 0.8

species OC
kind smoke
colormap greys
range 0 200
scale linear
opacity 0 0.05 0.2 0.45 0.8
