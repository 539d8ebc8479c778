"""jointwear.wear"""
